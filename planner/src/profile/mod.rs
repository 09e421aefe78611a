//! Single-dimension motion profiles: trapezoidal and jerk-limited S-curve.
//!
//! Every instruction of the planner moves a scalar (an axis position, or a path
//! length along a coordinated move) with a [`Profile`]: a time-ordered list of
//! constant-jerk segments, sampleable at any time with [`Profile::sample`].
//!
//! * [`Profile::to_position`] plans from an arbitrary start [`State`]
//!   (position, velocity, acceleration) to a target position, arriving with a
//!   given final speed (0 for a stop at the target, non-zero for a blend into
//!   the next move). Rest-to-rest profiles are time-optimal for their limits.
//! * [`Profile::to_velocity`] changes velocity only (stops, jogs).
//!
//! Re-planning mid-motion (aborting, blending) is sampling the running profile
//! at the current time and planning a new one from that [`State`].
//!
//! # Shape
//! A position profile is *ramp → cruise → ramp*: a velocity change from
//! the start state to a peak velocity `v_p`, a cruise at `v_p`, and a velocity
//! change to the final speed. The planner picks the largest `v_p ≤ v_max`
//! whose two ramps fit in the distance. A ramp's distance, and its first
//! and second derivatives by its end speed, are closed-form per regime
//! (acceleration limit held or not: a quadratic, or a cubic in the peak
//! acceleration, Ruckig's profile shapes), so the peak is a root found by
//! a power-law step from afar and quadratic-model steps near it — exact in
//! one step where both ramps hold their limit, a handful of evaluations
//! otherwise, with no ramp built until the peak is known. An S-curve ramp is
//! the classic three-phase jerk ramp (jerk up, constant acceleration, jerk
//! down), so a rest-to-rest S-curve has the seven phases of the textbook
//! double-S. One more shape covers an axis that is already decelerating
//! towards a target beyond its braking point but short of where ending the
//! deceleration would carry it: it decelerates less hard first, then brakes
//! (no stop-and-creep). With these the planner is time-optimal from any
//! start state that keeps the limits when raising and lowering the speed
//! share their limits: `tests/state_to_state.rs` matches Ruckig's
//! time-optimal durations within 1e-9 on 100,000 such cases, and on
//! 100,000 more with different accel and decel limits (one jerk: Ruckig
//! has one) on moves that do not reverse. With different accel and decel
//! jerks too it matches, within 1e-9 on 100,000 cases, the optimum that a
//! 30-digit bisection finds for the moves whose optimal shape is known in
//! closed form (forwards, from no acceleration or a rising one, to targets
//! beyond the lowest peak's ramps); no public solver covers other starts
//! with such jerks, and there the planner holds every limit (100,000
//! seeded cases). A reversal with different limits uses the
//! smaller pair throughout, which holds them but is not time-optimal across
//! zero speed — except where ending its acceleration with the smaller jerk
//! would carry the speed past `v_max` on the far side: there each phase
//! uses its own jerk (decel jerk down to zero speed, accel jerk as the speed
//! rises), which peaks at the least speed any plan can.
//!
//! # Limits, and where they apply
//! A phase that raises the speed |v| uses the *acceleration* limit and the
//! *accel jerk*; one that lowers it uses the *deceleration* limit and the
//! *decel jerk* — as the Logix accel and decel jerks are defined. So a stop
//! issued while the axis still accelerates first ends the acceleration with
//! the accel jerk and only then decelerates: the speed never passes
//! `v_max` when the start state lets it stay within. A ramp that reverses
//! the direction of travel uses the smaller of each pair (it both lowers and
//! raises the speed), after easing, while the speed still falls, an
//! acceleration the far side could not end in time; where that would still
//! pass `v_max`, it falls to zero speed with the decel jerk and ends the
//! acceleration left with the accel jerk. Choices the textbooks
//! leave open, made here:
//! * a trapezoidal profile ignores the start acceleration (acceleration may
//!   jump, by definition of a trapezoid);
//! * a start speed above `v_max` (a re-plan with a lower speed) is brought down
//!   to `v_max` with the deceleration limits, as Logix decelerates to a
//!   lowered speed; a start acceleration above the limit is first ramped back
//!   to the limit with the ramp's jerk;
//! * a start whose acceleration cannot end before the speed passes `v_max`
//!   (v + a²/2j above it) peaks at that coast velocity, the least the jerk
//!   allows; [`Profile::peak_speed`] tells a caller to flag it;
//! * when the end speed cannot be reached in the distance available (a blend
//!   into a move that is too short), the profile ends at the highest speed it
//!   can reach — [`Profile::final_state`] tells the caller which;
//! * when the target lies behind the point where the axis can stop, the
//!   profile brakes, reverses, and approaches it from the other side.

mod jerk;
mod kinematics;
mod peak;
mod ramp;

pub use jerk::{JerkUnits, JerkUnitsError, jerk_from_percent_of_time, jerk_to_percent_of_time, jerk_to_units_per_sec3};
pub use kinematics::{Limits, LimitsError, Sample, Shape, State};
use peak::{PeakRamps, newton_at_most, softened_brake};
use ramp::{Phase, Ramp, coast_velocity, phase_distance, ramp_distance};

/// One constant-jerk piece of a profile, starting at `t0_s`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Segment {
    t0_s: f64,
    duration_s: f64,
    start: State,
    jerk: f64,
}

impl Segment {
    fn at(&self, tau: f64) -> Sample {
        let State {
            position: p,
            velocity: v,
            acceleration: a,
        } = self.start;
        let j = self.jerk;
        Sample {
            position: p + phase_distance(v, a, j, tau),
            velocity: v + tau * (a + tau * j / 2.0),
            acceleration: a + tau * j,
            jerk: j,
        }
    }
}

/// A planned single-dimension motion, sampleable at any time.
///
/// Time 0 is the start of the profile; before it the start state holds, after
/// [`Profile::duration_s`] the final state holds and the position keeps
/// advancing at the final speed (a blended profile hands over moving).
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    segments: Vec<Segment>,
    start: State,
    final_state: State,
    duration_s: f64,
    overshoot: Option<Overshoot>,
}

/// How a profile overshoots (see [`Profile::overshoot`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Overshoot {
    /// The speed limit the profile passes, if it does.
    speed_limit: Option<f64>,
    /// The target it passes, and the direction it approached it from.
    passes: Option<(f64, f64)>,
}

impl Profile {
    /// A profile that stays at `state` (with zero acceleration) forever.
    pub fn hold(state: State) -> Self {
        let state = State {
            acceleration: 0.0,
            ..state
        };
        Self {
            segments: Vec::new(),
            overshoot: None,
            start: state,
            final_state: state,
            duration_s: 0.0,
        }
    }

    /// Plans from `start` to `target_position`, arriving with speed
    /// `final_speed` (≥ 0, in the direction of travel at arrival).
    ///
    /// The final speed actually reached is in [`Profile::final_state`]: it is
    /// lower than asked when the distance is too short to reach it, and 0 when
    /// the target lies behind the stopping point (the profile then reverses).
    /// A negative or non-finite `final_speed` is taken as 0; a non-finite
    /// target gives a profile that holds the start position (callers validate
    /// operands before planning).
    pub fn to_position(start: State, target_position: f64, final_speed: f64, limits: &Limits) -> Self {
        let mut stopping = None;
        let mut profile = Self::plan_position(start, target_position, final_speed, limits, &mut stopping);
        let s = sanitize(start, limits);
        let toward = target_position - s.position;
        let passes = s.velocity * toward > 0.0
            && toward * (toward - stopping.unwrap_or_else(|| stopping_distance(s, limits))) < 0.0
            && target_position.is_finite();
        profile.flag_overshoot(limits, passes.then_some((target_position, toward.signum())));
        profile
    }

    /// [`Profile::to_position`] without the overshoot flag; `stopping` gets
    /// the start's stopping distance where the plan computes it.
    fn plan_position(
        start: State,
        target_position: f64,
        final_speed: f64,
        limits: &Limits,
        stopping: &mut Option<f64>,
    ) -> Self {
        let requested_final_speed = if final_speed.is_finite() && final_speed > 0.0 {
            final_speed
        } else {
            0.0
        };
        let final_speed = requested_final_speed;
        if !target_position.is_finite() || !start.position.is_finite() {
            return Self::hold(start);
        }
        let start = sanitize(start, limits);
        let distance = target_position - start.position;
        // The least distance to the target's side: brake to the final speed.
        let toward = if distance < 0.0 { -1.0 } else { 1.0 };
        let mut final_speed = final_speed;
        let brake = |vt: f64| ramp_distance(start.velocity, start.acceleration, vt, limits);
        let mut braking = brake(toward * final_speed);
        if toward * (distance - braking) < 0.0 && final_speed > 0.0 {
            // Overshoots even so: stop there, come back, arrive at rest.
            final_speed = 0.0;
            braking = brake(0.0);
        }
        if final_speed == 0.0 {
            *stopping = Some(braking);
        }
        let beyond = distance - braking;
        // Which way the axis travels at arrival.
        let dir = if beyond > 0.0 {
            1.0
        } else if beyond < 0.0 {
            -1.0
        } else {
            let brake = Ramp::new(start.velocity, start.acceleration, toward * final_speed, limits);
            let mut profile = Self::from_ramps(start, &[&brake], limits);
            profile.final_state.position = target_position;
            return profile;
        };
        let v0 = dir * start.velocity;
        let a0 = dir * start.acceleration;
        let dist = dir * distance;
        let v_max = limits.velocity;
        // Distance the root search may leave over or under: 1e-13 of the
        // move, above the rounding of ramps whose distances nearly cancel
        // and at most a tenth of the miss (`tolerance` below) that gives
        // the ramps up. The cruise absorbs a shortfall exactly, the final
        // state's exact target an excess.
        let tol = 1e-13 * dist.abs();
        let v_free = coast_velocity(v0, a0, limits);
        let mut vf = final_speed;
        let lo = vf.max(v_free.max(0.0)).min(v_max);
        let mut up = PeakRamps::new((v0, a0), Some(vf), (lo, v_max), dist, limits);
        let at_max = up.excess_at_high();
        let peak;
        if at_max[0] <= 0.0 {
            peak = v_max;
        } else {
            up.fix_course();
            let at_lo = up.excess(lo)[0];
            if lo >= vf && at_lo <= 0.0 {
                peak = newton_at_most(lo, v_max, at_lo, at_max, tol, |vp| up.excess(vp));
            } else if v_free > vf {
                if a0 < 0.0
                    && v0 <= v_max
                    && let Some((first, rest)) = softened_brake(start, dir, vf, dist, limits)
                {
                    return Profile::in_travel_frame(start, dir, &[&first, &rest], target_position, vf, limits);
                }
                // Too close to cruise above the start speed: brake earlier.
                // Braking straight to `vf` fits because stopping fits.
                peak = PeakRamps::new((v0, a0), Some(vf), (vf, v_free.min(v_max)), dist, limits).solve(tol);
            } else {
                // Cannot even reach `vf` in the distance: end as fast as possible.
                vf = PeakRamps::new((v0, a0), None, (0.0, vf), dist, limits).solve(tol);
                peak = vf;
            }
        }
        // The ramps' own integration gives the distance they cover; the
        // cruise between them takes the rest.
        let travel_start = State {
            position: 0.0,
            velocity: v0,
            acceleration: a0,
        };
        let mut to_peak = Integrated::new(travel_start, limits);
        to_peak.ramp(&Ramp::new(v0, a0, peak, limits));
        let mut from_peak = Integrated::continuing(&to_peak);
        from_peak.ramp(&Ramp::new(peak, 0.0, vf, limits));
        let cruise_len = dist - from_peak.state.position;
        let tolerance = 1e-12 * (1.0 + dist.abs() + start.position.abs());
        let at_rest = start.velocity == 0.0 && start.acceleration == 0.0;
        if !at_rest && (cruise_len < -tolerance || (cruise_len > tolerance && peak <= 1e-9 * v_max)) {
            // The ramps do not meet (the acceleration limits switch between
            // braking and reversing, so the ramp distance jumps near zero
            // speed): stop first, then move from rest, which always fits
            // (from rest the ramp distance is continuous, so this recursion
            // is one level deep).
            let stop = Self::to_velocity(start, 0.0, limits);
            let rest = State::at_rest(stop.final_state.position);
            return stop.then(Self::plan_position(
                rest,
                target_position,
                requested_final_speed,
                limits,
                &mut None,
            ));
        }
        let cruise_s = if cruise_len > 0.0 && peak > 1e-9 * v_max {
            cruise_len / peak
        } else {
            0.0
        };
        Self::with_cruise(start, dir, &to_peak, cruise_s, &from_peak, target_position, vf)
    }

    /// The profile of a ramp to the peak speed, a cruise of `cruise_s` at
    /// the speed it reached and a ramp from the peak (integrated from there
    /// without the cruise, so moved on by it here), planned in the frame
    /// where travel is positive (`dir` · the axis) and mapped onto the axis
    /// from `start`, ending at `target_position` with speed `final_speed`
    /// in the direction of travel.
    fn with_cruise(
        start: State,
        dir: f64,
        to_peak: &Integrated,
        cruise_s: f64,
        from_peak: &Integrated,
        target_position: f64,
        final_speed: f64,
    ) -> Self {
        let onto = |seg: &Segment, shift_s: f64, shift: f64| Segment {
            t0_s: seg.t0_s + shift_s,
            duration_s: seg.duration_s,
            start: State {
                position: start.position + dir * (seg.start.position + shift),
                velocity: dir * seg.start.velocity,
                acceleration: dir * seg.start.acceleration,
            },
            jerk: dir * seg.jerk,
        };
        let mut segments = Vec::with_capacity(to_peak.count + 1 + from_peak.count);
        segments.extend(to_peak.segments().iter().map(|seg| onto(seg, 0.0, 0.0)));
        let mut shift = 0.0;
        if cruise_s > 0.0 {
            let cruise = Segment {
                t0_s: to_peak.t_s,
                duration_s: cruise_s,
                start: State {
                    acceleration: 0.0,
                    ..to_peak.state
                },
                jerk: 0.0,
            };
            shift = to_peak.state.velocity * cruise_s;
            segments.push(onto(&cruise, 0.0, 0.0));
        }
        segments.extend(from_peak.segments().iter().map(|seg| onto(seg, cruise_s, shift)));
        Self {
            segments,
            start,
            final_state: State {
                position: target_position,
                velocity: dir * final_speed,
                acceleration: 0.0,
            },
            duration_s: from_peak.t_s + cruise_s,
            overshoot: None,
        }
    }

    /// The profile of `ramps` planned in the frame where travel is positive (`dir` · the axis),
    /// mapped back onto the axis from `start`, ending at `target_position`
    /// with speed `final_speed` in the direction of travel.
    fn in_travel_frame(
        start: State,
        dir: f64,
        ramps: &[&Ramp],
        target_position: f64,
        final_speed: f64,
        limits: &Limits,
    ) -> Self {
        let mirrored_start = State {
            position: 0.0,
            velocity: dir * start.velocity,
            acceleration: dir * start.acceleration,
        };
        let mut profile = Self::from_ramps(mirrored_start, ramps, limits);
        profile.onto_axis(start, dir, target_position, final_speed);
        profile
    }

    /// This profile, planned in the frame where travel is positive (`dir` ·
    /// the axis) from position 0, mapped onto the axis from `start`, ending
    /// exactly at `target_position` with speed `final_speed` in the
    /// direction of travel.
    fn onto_axis(&mut self, start: State, dir: f64, target_position: f64, final_speed: f64) {
        self.mirror_and_shift(dir, start.position);
        self.start = start;
        self.final_state = State {
            position: target_position,
            velocity: dir * final_speed,
            acceleration: 0.0,
        };
    }

    /// Changes velocity from `start` to `target_velocity` (signed) and holds it.
    ///
    /// Used for stops (`target_velocity = 0`) and jogs. The position after the
    /// ramp keeps advancing at `target_velocity`; [`Profile::final_state`]
    /// gives the state at the end of the ramp. `target_velocity` is clamped to
    /// ±`limits.velocity()`; a non-finite one is taken as 0.
    pub fn to_velocity(start: State, target_velocity: f64, limits: &Limits) -> Self {
        let vt = if target_velocity.is_finite() {
            target_velocity.clamp(-limits.velocity, limits.velocity)
        } else {
            0.0
        };
        let start = sanitize(start, limits);
        let ramp = Ramp::new(start.velocity, start.acceleration, vt, limits);
        let mut profile = Self::from_ramps(start, &[&ramp], limits);
        profile.final_state.velocity = vt;
        profile.flag_overshoot(limits, None);
        profile
    }

    fn from_ramps(start: State, ramps: &[&Ramp], limits: &Limits) -> Self {
        let mut segments = Vec::with_capacity(4 * ramps.len());
        let mut at = Integrated::new(start, limits);
        for ramp in ramps {
            at.ramp(ramp);
            at.move_into(&mut segments);
        }
        Self {
            segments,
            overshoot: None,
            start,
            final_state: State {
                acceleration: 0.0,
                ..at.state
            },
            duration_s: at.t_s,
        }
    }

    /// This profile followed by `next` (which must start where this one ends).
    fn then(mut self, next: Profile) -> Profile {
        let offset = self.duration_s;
        self.segments.extend(next.segments.into_iter().map(|s| Segment {
            t0_s: s.t0_s + offset,
            ..s
        }));
        self.duration_s += next.duration_s;
        self.final_state = next.final_state;
        self
    }

    fn mirror_and_shift(&mut self, dir: f64, offset: f64) {
        for seg in &mut self.segments {
            seg.start.position = offset + dir * seg.start.position;
            seg.start.velocity *= dir;
            seg.start.acceleration *= dir;
            seg.jerk *= dir;
        }
    }

    /// Moves the whole profile by `delta` along the position axis (a position
    /// redefinition, MRP): velocities and timing are unchanged.
    pub fn shift_position(&mut self, delta: f64) {
        for seg in &mut self.segments {
            seg.start.position += delta;
        }
        self.start.position += delta;
        self.final_state.position += delta;
    }

    /// The constant-jerk phases in time order: start time (s), duration (s)
    /// and the sample at the phase's start, whose jerk holds throughout.
    pub fn phases(&self) -> impl Iterator<Item = (f64, f64, Sample)> + '_ {
        self.segments.iter().map(|s| (s.t0_s, s.duration_s, s.at(0.0)))
    }

    fn flag_overshoot(&mut self, limits: &Limits, passes: Option<(f64, f64)>) {
        let speed_limit = (self.peak_speed() > limits.velocity * (1.0 + 1e-12)).then_some(limits.velocity);
        self.overshoot = (speed_limit.is_some() || passes.is_some()).then_some(Overshoot { speed_limit, passes });
    }

    /// Whether the profile overshoots: its speed passes the limit (a start
    /// state that cannot keep it — a stop issued while accelerating with a
    /// smaller decel jerk, a speed lowered mid-move), or it passes its
    /// target and comes back (the target lies behind where the axis can
    /// stop — the overshoot the Logix documents warn of when the
    /// deceleration is decreased while a move decelerates).
    pub fn overshoot(&self) -> bool {
        self.overshoot.is_some()
    }

    /// Whether the profile is overshooting at `t_s`: above the speed limit,
    /// or past the target it comes back to.
    pub fn overshoot_at(&self, t_s: f64) -> bool {
        let Some(o) = self.overshoot else {
            return false;
        };
        if t_s >= self.duration_s {
            return false;
        }
        let s = self.sample(t_s);
        o.speed_limit.is_some_and(|v| s.velocity.abs() > v * (1.0 + 1e-12))
            || o.passes
                .is_some_and(|(target, toward)| toward * (s.position - target) > 0.0)
    }

    /// The highest speed |v| anywhere in the profile, its start and final
    /// state included (exact: inside a phase the speed peaks where the
    /// acceleration crosses zero).
    pub fn peak_speed(&self) -> f64 {
        let mut peak = self.start.velocity.abs().max(self.final_state.velocity.abs());
        let mut raise = |speed: f64| {
            if speed > peak {
                peak = speed;
            }
        };
        // A segment ends where the next starts; inside one, the speed has
        // an extremum only where the acceleration changes sign.
        for seg in &self.segments {
            let (v, a, j) = (seg.start.velocity, seg.start.acceleration, seg.jerk);
            raise(v.abs());
            if a * (a + j * seg.duration_s) < 0.0 {
                let t = -a / j;
                raise((v + t * (a + j * t / 2.0)).abs());
            }
        }
        if let Some(last) = self.segments.last() {
            raise(last.at(last.duration_s).velocity.abs());
        }
        peak
    }

    /// Duration in seconds until the final state is reached.
    pub fn duration_s(&self) -> f64 {
        self.duration_s
    }

    /// The state the profile started from.
    pub fn start_state(&self) -> State {
        self.start
    }

    /// The state at [`Profile::duration_s`] (position exactly the target for
    /// position profiles; velocity the speed actually reached).
    pub fn final_state(&self) -> State {
        self.final_state
    }

    /// Samples the profile at time `t_s` (seconds since its start).
    pub fn sample(&self, t_s: f64) -> Sample {
        if t_s >= self.duration_s || t_s.is_nan() {
            let f = self.final_state;
            let extra = if t_s.is_nan() { 0.0 } else { t_s - self.duration_s };
            return Sample {
                position: f.position + f.velocity * extra,
                velocity: f.velocity,
                acceleration: 0.0,
                jerk: 0.0,
            };
        }
        if t_s <= 0.0 || self.segments.is_empty() {
            let s = self.start;
            return Sample {
                position: s.position,
                velocity: s.velocity,
                acceleration: s.acceleration,
                jerk: 0.0,
            };
        }
        let i = self.segments.partition_point(|s| s.t0_s <= t_s).saturating_sub(1);
        let seg = &self.segments[i];
        seg.at((t_s - seg.t0_s).min(seg.duration_s))
    }

    /// Start time of the final deceleration: the trailing run of segments in
    /// which the speed only falls (the "deceleration point" where Logix's
    /// No Decel termination starts its blend). The duration for a profile
    /// that ends without slowing down; 0 for an empty one.
    pub fn deceleration_start_s(&self) -> f64 {
        let mut t = self.duration_s;
        for seg in self.segments.iter().rev() {
            let end = seg.at(seg.duration_s);
            if end.velocity.abs() < seg.start.velocity.abs() {
                t = seg.t0_s;
            } else {
                break;
            }
        }
        t
    }

    /// Whether the profile is in a phase that raises the speed at `t_s`
    /// (the Logix `.ACCEL` bit), and one that lowers it (`.DECEL`).
    pub fn accel_decel_at(&self, t_s: f64) -> (bool, bool) {
        if t_s >= self.duration_s || t_s < 0.0 {
            return (false, false);
        }
        let s = self.sample(t_s);
        let raising = s.velocity * s.acceleration > 0.0 || (s.velocity == 0.0 && s.acceleration != 0.0);
        let lowering = s.velocity * s.acceleration < 0.0;
        (raising, lowering)
    }
}

/// Phases integrated one after the other into segments (a ramp's worth
/// at a time): the state and time reached, in the frame they are planned
/// in.
struct Integrated {
    segments: [Segment; 5],
    count: usize,
    state: State,
    t_s: f64,
}

impl Integrated {
    /// From `start` at time 0 (a trapezoid ignores its acceleration).
    fn new(start: State, limits: &Limits) -> Self {
        let mut state = start;
        if matches!(limits.shape, Shape::Trapezoidal) {
            state.acceleration = 0.0;
        }
        Self {
            segments: [Segment::default(); 5],
            count: 0,
            state,
            t_s: 0.0,
        }
    }

    /// From where `before` ends, with no segments yet.
    fn continuing(before: &Integrated) -> Self {
        Self {
            segments: [Segment::default(); 5],
            count: 0,
            state: before.state,
            t_s: before.t_s,
        }
    }

    /// Appends one phase (none if it has no duration); at most five
    /// before [`Integrated::move_into`].
    fn phase(&mut self, phase: Phase) {
        if phase.duration_s <= 0.0 {
            return;
        }
        if let Some(a) = phase.set_acceleration {
            self.state.acceleration = a;
        }
        let seg = Segment {
            t0_s: self.t_s,
            duration_s: phase.duration_s,
            start: self.state,
            jerk: phase.jerk,
        };
        self.state = seg.at(phase.duration_s).state();
        if phase.set_acceleration.is_some() {
            self.state.acceleration = 0.0;
        }
        self.t_s += phase.duration_s;
        self.segments[self.count] = seg;
        self.count += 1;
    }

    /// Appends a ramp's phases (at most five).
    fn ramp(&mut self, ramp: &Ramp) {
        for phase in ramp.phases() {
            self.phase(phase);
        }
    }

    fn segments(&self) -> &[Segment] {
        &self.segments[..self.count]
    }

    /// Moves the segments integrated so far onto the end of `out`; the
    /// state and time go on from where they are.
    fn move_into(&mut self, out: &mut Vec<Segment>) {
        out.extend_from_slice(self.segments());
        self.count = 0;
    }
}

/// Signed distance an axis in `state` travels until it stands still, braking
/// with `limits` (the deceleration ramp of a stop).
pub fn stopping_distance(state: State, limits: &Limits) -> f64 {
    let state = sanitize(state, limits);
    ramp_distance(state.velocity, state.acceleration, 0.0, limits)
}

fn sanitize(state: State, limits: &Limits) -> State {
    let finite = |x: f64| if x.is_finite() { x } else { 0.0 };
    let mut s = State {
        position: state.position,
        velocity: finite(state.velocity),
        acceleration: finite(state.acceleration),
    };
    if matches!(limits.shape, Shape::Trapezoidal) {
        s.acceleration = 0.0;
    }
    s
}

#[cfg(test)]
mod tests;
