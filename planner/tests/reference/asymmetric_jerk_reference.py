"""Writes asymmetric_jerk.txt: time-optimal durations, computed in 30-digit
arithmetic, for moves whose accel and decel limits and jerks all differ, for
planner/tests/state_to_state.rs.

Dev-time only (the table is committed; tests never run Python):

    pip install mpmath
    python3 planner/tests/reference/asymmetric_jerk_reference.py

No public solver has a jerk that depends on whether the speed rises or falls
(Ruckig has one jerk), so this reference covers the moves whose time-optimal
shape is known in closed form: a start at rest or moving forwards with an
acceleration of zero or up to the limit (one the speed limit lets end), a
target ahead at least as far as the ramps through the lowest peak (the
final speed, or the coast speed above it) take. Such a move raises the
speed with the accel limit and jerk to a peak v_p, cruises, and lowers it
with the decel limit and jerk (each ramp, at full jerk, is time-optimal for
its speed change, and the total time falls as v_p rises while the cruise is
not negative), so the optimum is the largest v_p <= v_max whose ramps fit
the distance: found here by bisection to 30
digits, independently of the planner's Newton search.

Limits and start states come from the SplitMix64 stream of
ruckig_state_to_state.py (its own seed); each line stores the target
(shortest round-trip) and the duration (13 significant digits).
"""

from mpmath import mp, mpf, sqrt

from splitmix import SplitMix64, write_table

CASES = 100_000

mp.dps = 30
SEED = 0x5EED_1E14


def draw(rng):
    """One case (mirrored in Rust)."""
    v = rng.scale(-4, 10)
    a = v * rng.scale(-3, 5)
    d = a * rng.scale(-2, 2)
    ja = a * a / v * rng.scale(-2, 7)
    jd = ja * rng.scale(-4, 3)
    p0 = (2.0 * rng.unit() - 1.0) * 100.0
    kind = rng.below(4)
    v0 = 0.0 if kind == 0 else v * rng.unit()
    a0 = a * rng.unit() if kind >= 2 else 0.0
    # An acceleration the speed limit lets end (the coast within v).
    while v0 + a0 * a0 / (2.0 * ja) > v:
        a0 *= 0.5
    vf = v * rng.unit() if rng.below(4) == 0 else 0.0
    k = rng.below(31)
    u = rng.unit()
    return v, a, d, ja, jd, p0, v0, a0, vf, k, u


def rise(v0, a0, vp, acc, jerk):
    """Distance and duration of the time-optimal rise from (v0, a0 >= 0) to
    (vp, 0), vp at least the coast speed v0 + a0^2/(2 jerk): the
    acceleration goes up to its peak (the limit or lower), holds, and comes
    back to zero, each at full jerk."""
    peak = min(acc, sqrt(jerk * (vp - v0) + a0 * a0 / 2))
    t1 = (peak - a0) / jerk
    v1 = v0 + (a0 + peak) / 2 * t1
    t3 = peak / jerk
    t2 = (vp - v1 - peak * peak / (2 * jerk)) / peak if peak > 0 else mpf(0)
    v2 = v1 + peak * t2
    distance = v0 * t1 + a0 * t1**2 / 2 + jerk * t1**3 / 6 + (v1 + v2) / 2 * t2 + v2 * t3 + peak * t3**2 / 2 - jerk * t3**3 / 6
    return distance, t1 + t2 + t3


def ramp(dv, acc, jerk):
    """Duration of a zero-to-zero-acceleration ramp changing the speed by dv
    (>= 0)."""
    if dv >= acc * acc / jerk:
        return dv / acc + acc / jerk
    return 2 * sqrt(dv / jerk)


def ramps(vp, v0, a0, vf, a, d, ja, jd):
    """Distance and duration of the two ramps through the peak vp."""
    d1, t1 = rise(v0, a0, vp, a, ja)
    t2 = ramp(vp - vf, d, jd)
    return d1 + (vp + vf) / 2 * t2, t1 + t2


def least_peak(v0, a0, vf, ja):
    """The lowest peak: the final speed or, above it, the coast speed."""
    return max(vf, v0 + a0 * a0 / (2 * ja))


def duration(dist, v, a, d, ja, jd, v0, a0, vf):
    lo = least_peak(v0, a0, vf, ja)
    hi = v
    d_hi, t_hi = ramps(hi, v0, a0, vf, a, d, ja, jd)
    if d_hi <= dist:
        return t_hi + (dist - d_hi) / hi
    for _ in range(120):
        mid = (lo + hi) / 2
        if ramps(mid, v0, a0, vf, a, d, ja, jd)[0] <= dist:
            lo = mid
        else:
            hi = mid
    d_lo, t_lo = ramps(lo, v0, a0, vf, a, d, ja, jd)
    return t_lo + (dist - d_lo) / lo if lo > 0 else t_lo


def main():
    rng = SplitMix64(SEED)
    lines = [
        "# Time-optimal durations (30-digit bisection) for planner/tests/state_to_state.rs;",
        "# written by asymmetric_jerk_reference.py (seed 0x5EED1E14): target, duration_s",
    ]
    for _ in range(CASES):
        v, a, d, ja, jd, p0, v0, a0, vf, k, u = draw(rng)
        m = [mpf(x) for x in (v, a, d, ja, jd, v0, a0, vf)]
        least, _ = ramps(least_peak(m[5], m[6], m[7], m[3]), m[5], m[6], m[7], m[1], m[2], m[3], m[4])
        span = v * v / min(a, d) + v * max(a / ja, d / jd)
        # Beyond the least distance by 2^-k of the span (k up to 30): from
        # just past "the ramps straight to the final speed" to far.
        target = p0 + float(least) + span * (1.0 + u) * 2.0 ** (-k)
        dist = mpf(target) - mpf(p0)
        t = duration(dist, *m)
        lines.append("%r %.13g" % (target, float(t)))
    write_table("asymmetric_jerk.txt", lines)


if __name__ == "__main__":
    main()
