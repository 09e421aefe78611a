//! The position cams of one slave axis: the active cam, a cam waiting for
//! its lock or pending, and the events the master's motion makes them raise.

use super::operand;
use super::{CamDirection, CamType, ExecutionMode, ExecutionSchedule, Mapc, MapcError, MasterDirection};
use crate::mccp::CamProfile;
use std::sync::Arc;

/// The slave axis' position cam status bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SlaveCamStatus {
    /// Position Cam Status.
    pub position_cam: bool,
    /// Position Cam Lock Status.
    pub lock: bool,
    /// Position Cam Pending Status.
    pub pending: bool,
}

/// What happened to an MAPC instruction (identified by its tag `T`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CamEvent<T> {
    /// The cam began interpolating the slave (`.AC` set).
    Active(T),
    /// The cam ended: `.IP` and `.AC` reset, its profile released; `.PC` set
    /// when `complete` (a Once cam that crossed its boundary).
    Ended {
        /// The instruction.
        tag: T,
        /// Whether it completed (Once mode) rather than being superseded,
        /// cancelled or stopped.
        complete: bool,
    },
    /// The cam's slave position overflowed (not a finite number): the cam
    /// ended (an [`CamEvent::Ended`] comes before this) and the instruction
    /// gets `.ER` with ERR 179 (Invalid Cam Profile Element: "overflow or not
    /// a number").
    Overflow(T),
}

/// An MAPC to start on a [`PositionCamAxis`].
#[derive(Debug, Clone)]
pub struct CamRequest<T, K> {
    /// The instruction (returned in events).
    pub tag: T,
    /// The master and its reference (the key handed to the master lookup).
    pub master: K,
    /// The validated operands.
    pub mapc: Mapc,
    /// The profile (already counted in its Status by the caller).
    pub profile: Arc<CamProfile>,
    /// The master's modulo period, if it is a modulo (rotary) axis: its
    /// Master Lock Position is then independent of the turns count.
    pub master_period: Option<f64>,
}

#[derive(Debug, Clone)]
struct Cam<T, K> {
    tag: T,
    master: K,
    profile: Arc<CamProfile>,
    sign: f64,
    mapc: Mapc,
    master_period: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
struct Run {
    clutch: f64,
    c_ref: f64,
    u_ref: f64,
    u_start: f64,
    slave_start: f64,
    f_start: f64,
    u: f64,
    slipping: bool,
    /// A Replace and Continue cam that took over from a slipping cam shows
    /// this slave position until the master picks up.
    hold: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
enum Phase {
    /// Waiting for the master to cross the lock position.
    Armed {
        prev: f64,
    },
    Running(Run),
}

#[derive(Debug, Clone)]
struct Active<T, K> {
    cam: Cam<T, K>,
    phase: Phase,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum WaitKind {
    Pending,
    Replacement { prev: f64 },
}

#[derive(Debug, Clone)]
struct Waiting<T, K> {
    cam: Cam<T, K>,
    kind: WaitKind,
}

/// The position cam process of one slave axis.
#[derive(Debug, Clone)]
pub struct PositionCamAxis<T, K> {
    direction_memory: Option<f64>,
    master_offset: f64,
    active: Option<Active<T, K>>,
    waiting: Option<Waiting<T, K>>,
}

impl<T, K> Default for PositionCamAxis<T, K> {
    fn default() -> Self {
        Self {
            direction_memory: None,
            master_offset: 0.0,
            active: None,
            waiting: None,
        }
    }
}

/// `F(u)`: the profile in the cam's execution mode.
pub(super) fn cam_value(profile: &CamProfile, mode: ExecutionMode, u: f64) -> f64 {
    match mode {
        ExecutionMode::Continuous => {
            let (x0, xn) = profile.master_range();
            let (y0, yn) = profile.slave_range();
            let period = xn - x0;
            let k = ((u - x0) / period).floor();
            let w = (u - k * period).clamp(x0, xn);
            profile.eval(w).slave + k * (yn - y0)
        }
        _ => profile.eval(u).slave,
    }
}

fn cycle(profile: &CamProfile, u: f64) -> f64 {
    let (x0, xn) = profile.master_range();
    ((u - x0) / (xn - x0)).floor()
}

impl<T: Copy + PartialEq, K: Copy + PartialEq> Cam<T, K> {
    fn value(&self, u: f64) -> f64 {
        cam_value(&self.profile, self.mapc.execution_mode, u)
    }

    fn slave_at(&self, run: &Run, u: f64) -> f64 {
        run.slave_start + self.sign * self.mapc.slave_scaling * (self.value(u) - run.f_start)
    }

    /// A fresh run locked at clutch position `c0` at cam coordinate `u0`.
    fn lock_at(&self, c0: f64, u0: f64, slave: f64) -> Run {
        Run {
            clutch: c0,
            c_ref: c0,
            u_ref: u0,
            u_start: u0,
            slave_start: slave,
            f_start: self.value(u0),
            u: u0,
            slipping: false,
            hold: None,
        }
    }

    /// The clutch and coordinate for master position `m`, without changing
    /// the run.
    fn follow(&self, run: &Run, m: f64) -> (f64, f64, bool) {
        let (c, slipping) = match self.mapc.master_direction {
            MasterDirection::Bidirectional => (m, false),
            MasterDirection::ForwardOnly if m >= run.clutch => (m, false),
            MasterDirection::ReverseOnly if m <= run.clutch => (m, false),
            _ => (run.clutch, true),
        };
        (c, run.u_ref + (c - run.c_ref) / self.mapc.master_scaling, slipping)
    }
}

/// Where the master, moving from `prev` to `now`, crossed (or reached) the
/// lock position in the schedule's direction; on a modulo master any
/// position `lock + k · period` counts.
fn crossing(schedule: ExecutionSchedule, lock: f64, period: Option<f64>, prev: f64, now: f64) -> Option<f64> {
    let (forward_ok, reverse_ok) = match schedule {
        ExecutionSchedule::ForwardOnly => (true, false),
        ExecutionSchedule::ReverseOnly => (false, true),
        ExecutionSchedule::Bidirectional => (true, true),
        ExecutionSchedule::Immediate | ExecutionSchedule::Pending => (false, false),
    };
    if now > prev && forward_ok {
        let at = period.map_or(lock, |p| lock + ((prev - lock) / p).ceil() * p);
        (prev <= at && at <= now).then_some(at)
    } else if now < prev && reverse_ok {
        let at = period.map_or(lock, |p| lock + ((prev - lock) / p).floor() * p);
        (now <= at && at <= prev).then_some(at)
    } else {
        None
    }
}

impl<T: Copy + PartialEq, K: Copy + PartialEq> PositionCamAxis<T, K> {
    /// The slave's status bits.
    pub fn status(&self) -> SlaveCamStatus {
        let replacement = matches!(
            self.waiting,
            Some(Waiting {
                kind: WaitKind::Replacement { .. },
                ..
            })
        );
        let lock = match &self.active {
            Some(Active {
                cam,
                phase: Phase::Running(run),
            }) => {
                let (x0, xn) = cam.profile.master_range();
                !run.slipping && (cam.mapc.execution_mode == ExecutionMode::Continuous || (x0..=xn).contains(&run.u))
            }
            _ => false,
        };
        SlaveCamStatus {
            position_cam: self.active.is_some() || replacement,
            lock,
            pending: self.waiting.is_some(),
        }
    }

    /// Whether a cam owns the slave now (active, running or waiting for its
    /// lock, or a replacement waiting): nothing else may command it.
    pub fn drives(&self) -> bool {
        let s = self.status();
        s.position_cam
    }

    /// The master offset (master offset moves), master units.
    pub fn master_offset(&self) -> f64 {
        self.master_offset
    }

    /// A master offset move: shifts the master position the cam sees by
    /// `delta` (the cam profile moves by −`delta` along the master).
    pub fn shift_master_offset(&mut self, delta: f64) {
        if delta.is_finite() {
            self.master_offset += delta;
        }
    }

    /// The slave's position was redefined by `delta` (MRP): the running cam
    /// continues from the shifted position.
    pub fn redefine_slave(&mut self, delta: f64) {
        if let Some(Active {
            phase: Phase::Running(run),
            ..
        }) = &mut self.active
        {
            run.slave_start += delta;
            if let Some(h) = run.hold.as_mut() {
                *h += delta;
            }
        }
    }

    /// The cam coordinate `u` of the running cam (unscaled cam master units).
    pub fn cam_coordinate(&self) -> Option<f64> {
        match &self.active {
            Some(Active {
                phase: Phase::Running(run),
                ..
            }) => Some(run.u),
            _ => None,
        }
    }

    /// The direction sign (+1 Same, −1 Opposite) the next cam would use for
    /// `direction`, and the memory after it.
    fn resolve(&mut self, direction: CamDirection) -> f64 {
        let previous = self.direction_memory.unwrap_or(1.0);
        let sign = match direction {
            CamDirection::Same => 1.0,
            CamDirection::Opposite => -1.0,
            CamDirection::Reverse => -previous,
            CamDirection::Unchanged => previous,
        };
        self.direction_memory = Some(sign);
        sign
    }

    /// Executes an MAPC. `slave` is the slave's command position now, and
    /// `master(key)` a master's position now (without the master offset).
    /// Returns the events of other cams it superseded and its own `Active`
    /// when it locks at once.
    ///
    /// # Errors
    /// ERR 13 (EXERR 10) when the Cam Lock Position is outside the profile's
    /// master range (not checked for Replace and Continue, which ignores it).
    pub fn start(
        &mut self,
        req: CamRequest<T, K>,
        slave: f64,
        master: impl Fn(K) -> f64,
    ) -> Result<Vec<CamEvent<T>>, MapcError> {
        let m = req.mapc;
        let (x0, xn) = req.profile.master_range();
        let lock_ignored =
            m.cam_type == CamType::ReplaceAndContinue && m.execution_schedule != ExecutionSchedule::Pending;
        if !lock_ignored && !(x0..=xn).contains(&m.cam_lock_position) {
            return Err(MapcError::ParameterOutOfRange {
                operand: operand::CAM_LOCK_POSITION,
                value: m.cam_lock_position,
            });
        }
        let sign = self.resolve(m.direction);
        let cam = Cam {
            tag: req.tag,
            master: req.master,
            profile: req.profile,
            sign,
            mapc: m,
            master_period: req.master_period.filter(|p| p.is_finite() && *p > 0.0),
        };
        let mut events = Vec::new();
        if m.execution_schedule == ExecutionSchedule::Pending {
            if let Some(w) = self.waiting.take() {
                events.push(CamEvent::Ended {
                    tag: w.cam.tag,
                    complete: false,
                });
            }
            self.waiting = Some(Waiting {
                cam,
                kind: WaitKind::Pending,
            });
            return Ok(events);
        }
        self.master_offset = 0.0;
        let now = master(cam.master) + self.master_offset;
        let replace = m.cam_type != CamType::NewCam && self.active.is_some();
        if replace {
            // A replacement cancels whatever waits.
            if let Some(w) = self.waiting.take() {
                events.push(CamEvent::Ended {
                    tag: w.cam.tag,
                    complete: false,
                });
            }
            if m.execution_schedule == ExecutionSchedule::Immediate {
                self.replace(cam, now, slave, &master, &mut events);
            } else {
                self.waiting = Some(Waiting {
                    cam,
                    kind: WaitKind::Replacement { prev: now },
                });
            }
            return Ok(events);
        }
        // A new cam: supersedes the active cam and a waiting replacement.
        if let Some(a) = self.active.take() {
            events.push(CamEvent::Ended {
                tag: a.cam.tag,
                complete: false,
            });
        }
        if matches!(
            self.waiting,
            Some(Waiting {
                kind: WaitKind::Replacement { .. },
                ..
            })
        ) && let Some(w) = self.waiting.take()
        {
            events.push(CamEvent::Ended {
                tag: w.cam.tag,
                complete: false,
            });
        }
        if m.execution_schedule == ExecutionSchedule::Immediate {
            let run = cam.lock_at(now, m.cam_lock_position, slave);
            events.push(CamEvent::Active(cam.tag));
            self.active = Some(Active {
                cam,
                phase: Phase::Running(run),
            });
        } else {
            self.active = Some(Active {
                cam,
                phase: Phase::Armed { prev: now },
            });
        }
        Ok(events)
    }

    /// Replaces the active cam by `cam` at master position `at` (master
    /// offset included) of the replacement's master.
    fn replace(
        &mut self,
        cam: Cam<T, K>,
        at: f64,
        slave_now: f64,
        master: &impl Fn(K) -> f64,
        events: &mut Vec<CamEvent<T>>,
    ) {
        let old = self.active.take();
        let mut run = None;
        if let Some(Active {
            cam: old_cam,
            phase: Phase::Running(old_run),
        }) = &old
        {
            let m_old = if old_cam.master == cam.master {
                at
            } else {
                master(old_cam.master) + self.master_offset
            };
            let (c_old, u_old, slipping) = old_cam.follow(old_run, m_old);
            let inherit = slipping
                && old_cam.mapc.master_direction == cam.mapc.master_direction
                && cam.mapc.master_direction != MasterDirection::Bidirectional;
            let c0 = if inherit { c_old } else { at };
            let slave_at = old_cam.slave_at(old_run, u_old);
            run = Some(match cam.mapc.cam_type {
                CamType::ReplaceAndContinue => Run {
                    clutch: c0,
                    c_ref: c0,
                    u_ref: u_old,
                    u_start: old_run.u_start,
                    slave_start: old_run.slave_start,
                    f_start: cam.value(old_run.u_start),
                    u: u_old,
                    slipping: false,
                    hold: inherit.then_some(slave_at),
                },
                _ => cam.lock_at(c0, cam.mapc.cam_lock_position, slave_at),
            });
        }
        if let Some(a) = old {
            events.push(CamEvent::Ended {
                tag: a.cam.tag,
                complete: false,
            });
        }
        let run = run.unwrap_or_else(|| cam.lock_at(at, cam.mapc.cam_lock_position, slave_now));
        events.push(CamEvent::Active(cam.tag));
        self.active = Some(Active {
            cam,
            phase: Phase::Running(run),
        });
    }

    /// Stops the position cam process (MAS/MCS with Stop Type All or Position
    /// Cam, or a shutdown): every cam ends, not complete.
    pub fn stop(&mut self) -> Vec<CamEvent<T>> {
        let mut events = Vec::new();
        if let Some(a) = self.active.take() {
            events.push(CamEvent::Ended {
                tag: a.cam.tag,
                complete: false,
            });
        }
        if let Some(w) = self.waiting.take() {
            events.push(CamEvent::Ended {
                tag: w.cam.tag,
                complete: false,
            });
        }
        events
    }

    /// One coarse update: `slave` is the slave's command position before it,
    /// `master(key)` the masters' positions now. Returns the slave's new
    /// command position (`None` when no cam commands it) and the events.
    ///
    /// A slave position that is not a finite number (extreme scalings or
    /// master travel overflowing `f64`) ends the active cam with
    /// [`CamEvent::Overflow`]; the slave holds where it was.
    pub fn update(&mut self, slave: f64, master: impl Fn(K) -> f64) -> (Option<f64>, Vec<CamEvent<T>>) {
        let (position, mut events) = self.advance(slave, master);
        if position.is_some_and(|p| !p.is_finite()) {
            if let Some(a) = self.active.take() {
                events.push(CamEvent::Ended {
                    tag: a.cam.tag,
                    complete: false,
                });
                events.push(CamEvent::Overflow(a.cam.tag));
            } else if let Some(CamEvent::Ended { tag, complete }) =
                events.iter_mut().rev().find(|e| matches!(e, CamEvent::Ended { .. }))
            {
                // A Once cam that ended at its boundary with an overflowing
                // end position: it did not complete.
                *complete = false;
                let tag = *tag;
                events.push(CamEvent::Overflow(tag));
            }
            return (Some(slave), events);
        }
        (position, events)
    }

    fn advance(&mut self, slave: f64, master: impl Fn(K) -> f64) -> (Option<f64>, Vec<CamEvent<T>>) {
        let mut events = Vec::new();
        let offset = self.master_offset;
        let mpos = |k: K| master(k) + offset;
        // A scheduled replacement whose master crossed its lock position.
        if let Some(Waiting {
            cam,
            kind: WaitKind::Replacement { prev },
        }) = &mut self.waiting
        {
            let now = mpos(cam.master);
            let lock = cam.mapc.master_lock_position;
            let crossed = crossing(cam.mapc.execution_schedule, lock, cam.master_period, *prev, now);
            *prev = now;
            if let Some(at) = crossed
                && let Some(w) = self.waiting.take()
            {
                self.replace(w.cam, at, slave, &mpos, &mut events);
            }
        }
        let Some(active) = &mut self.active else {
            return (None, events);
        };
        let cam = &active.cam;
        let m = mpos(cam.master);
        let mut run = match active.phase {
            Phase::Armed { prev } => {
                let lock = cam.mapc.master_lock_position;
                let Some(at) = crossing(cam.mapc.execution_schedule, lock, cam.master_period, prev, m) else {
                    active.phase = Phase::Armed { prev: m };
                    return (Some(slave), events);
                };
                events.push(CamEvent::Active(cam.tag));
                cam.lock_at(at, cam.mapc.cam_lock_position, slave)
            }
            Phase::Running(run) => run,
        };
        let (c, u, slipping) = cam.follow(&run, m);
        let (x0, xn) = cam.profile.master_range();
        let pending = matches!(
            self.waiting,
            Some(Waiting {
                kind: WaitKind::Pending,
                ..
            })
        );
        // Where the cam ends this update, if it does: the boundary crossed.
        let boundary = match cam.mapc.execution_mode {
            ExecutionMode::Once => (!(x0..=xn).contains(&u)).then(|| u.clamp(x0, xn)),
            ExecutionMode::Persistent if pending => (!(x0..=xn).contains(&u)).then(|| u.clamp(x0, xn)),
            ExecutionMode::Continuous if pending => {
                // The end of the cycle `u` was in: its end going forward,
                // its start going back (however far the master went).
                let (k0, k1) = (cycle(&cam.profile, run.u), cycle(&cam.profile, u));
                (k1 != k0).then_some(x0 + (xn - x0) * if k1 > k0 { k0 + 1.0 } else { k0 })
            }
            _ => None,
        };
        let Some(ub) = boundary else {
            run.clutch = c;
            run.u = u;
            run.slipping = slipping;
            let s = match run.hold {
                Some(h) if slipping => h,
                _ => {
                    run.hold = None;
                    cam.slave_at(&run, u)
                }
            };
            active.phase = Phase::Running(run);
            return (Some(s), events);
        };
        // The cam ends at `ub`; a Pending cam takes over there.
        let slave_end = cam.slave_at(&run, ub);
        let c_end = run.c_ref + (ub - run.u_ref) * cam.mapc.master_scaling;
        let complete = cam.mapc.execution_mode == ExecutionMode::Once;
        let old_master = cam.master;
        let Some(a) = self.active.take() else {
            return (Some(slave_end), events);
        };
        events.push(CamEvent::Ended {
            tag: a.cam.tag,
            complete,
        });
        if pending && let Some(w) = self.waiting.take() {
            let mut next = w.cam;
            next.master = old_master;
            let mut run = next.lock_at(c_end, next.mapc.cam_lock_position, slave_end);
            let (c, u, slipping) = next.follow(&run, m);
            run.clutch = c;
            run.u = u;
            run.slipping = slipping;
            let s = next.slave_at(&run, u);
            events.push(CamEvent::Active(next.tag));
            self.active = Some(Active {
                cam: next,
                phase: Phase::Running(run),
            });
            return (Some(s), events);
        }
        (Some(slave_end), events)
    }
}
