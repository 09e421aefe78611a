//! The cases of `ruckig_state_to_state.txt`, drawn from the SplitMix64
//! stream that `ruckig_state_to_state.py` repeats bit for bit: shared by
//! the test that checks the planner against the table
//! (`tests/state_to_state.rs`) and the benchmark that times it on the
//! cases Ruckig is timed on (`benches/profiles.rs`, `ruckig_timing.py`).

use planner::profile::State;

/// The seed of the table's stream.
pub const SEED: u64 = 0x5EED_0014;

/// Sebastiano Vigna's SplitMix64 generator (its state).
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }
    /// Uniform in 0..n (with the modulo's slight bias, as in Python).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    /// (1 + u)·2^k, k uniform in lo..=hi.
    pub fn scale(&mut self, lo: i32, hi: i32) -> f64 {
        let k = lo + self.below((hi - lo + 1) as u64) as i32;
        (1.0 + self.unit()) * 2f64.powi(k)
    }
}

/// One case of the Ruckig table: the same draws, in the same order, as
/// `draw` in the generator.
pub struct Case {
    pub v: f64,
    pub a: f64,
    pub j: f64,
    pub start: State,
    pub vf: f64,
}

pub fn draw(rng: &mut SplitMix64) -> Case {
    let v = rng.scale(-4, 10);
    let a = v * rng.scale(-3, 5);
    let j = a * a / v * rng.scale(-2, 7);
    let p0 = (2.0 * rng.unit() - 1.0) * 100.0;
    let kind = rng.below(8);
    let (mut v0, mut a0) = (0.0, 0.0);
    if kind != 0 {
        v0 = v * (2.0 * rng.unit() - 1.0);
        a0 = a * (2.0 * rng.unit() - 1.0);
        if kind == 1 {
            a0 = 0.0;
        }
        a0 = keeping(v0, a0, j, -v..=v);
    }
    let vf = if rng.below(4) == 0 { v * rng.unit() } else { 0.0 };
    // The target recipe's draws (nearness, exponent, fraction, side): the
    // table holds the target itself.
    let _ = (rng.below(3), rng.below(21), rng.unit(), rng.below(2));
    Case {
        v,
        a,
        j,
        start: State {
            position: p0,
            velocity: v0,
            acceleration: a0,
        },
        vf,
    }
}

/// What Ruckig found for a case of `ruckig_state_to_state.txt`.
pub struct Solved<'t> {
    /// The target position.
    pub target: f64,
    /// The sign of the final velocity: `+`, `-` or `0`.
    pub sign: &'t str,
    /// The profile's duration, s.
    pub duration_s: f64,
}

/// The table's rows in order (its comment lines skipped): each one's case,
/// and what Ruckig found for it (`None` for a row whose duration is `x`:
/// no profile).
pub fn rows(table: &str) -> impl Iterator<Item = (Case, Option<Solved<'_>>)> {
    let mut rng = SplitMix64(SEED);
    table.lines().filter(|l| !l.starts_with('#')).map(move |line| {
        let case = draw(&mut rng);
        let mut fields = line.split(' ');
        let mut field = || fields.next().expect("three fields: target, sign, duration");
        let (target, sign, duration) = (field(), field(), field());
        let solved = (duration != "x").then(|| Solved {
            target: target.parse().expect("a target"),
            sign,
            duration_s: duration.parse().expect("a duration"),
        });
        (case, solved)
    })
}

/// `a0` halved (at most 60 times) until ending it with the jerk `j` from
/// the speed `v0` arrives at a speed in `speeds`, or 0 where it does not:
/// the generators' rule for a start that can keep the velocity limit.
pub fn keeping(v0: f64, mut a0: f64, j: f64, speeds: std::ops::RangeInclusive<f64>) -> f64 {
    for _ in 0..60 {
        let coast = v0 + a0 * a0.abs() / (2.0 * j);
        if speeds.contains(&coast) {
            return a0;
        }
        a0 *= 0.5;
    }
    0.0
}
