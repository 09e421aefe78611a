"""Writes ruckig_state_to_state.txt: Ruckig's time-optimal durations for the
state-to-state cases that planner/tests/state_to_state.rs draws.

Dev-time only (the table is committed; tests never run Python):

    pip install ruckig==0.19.4
    python3 planner/tests/reference/ruckig_state_to_state.py

Limits and start states come from a SplitMix64 stream that the Rust test
repeats bit for bit (only +, -, *, / and sqrt, which IEEE 754 rounds the same
in both languages). The target depends on where Ruckig's own time-optimal stop
ends, so each line stores it (shortest round-trip), then the sign of the
final velocity (+, - or 0) and Ruckig's duration (13 significant digits), or
`x` where Ruckig reports an error.

Ruckig's model equals the planner's when the acceleration and jerk limits are
the same for raising and lowering the speed and the start state can keep the
velocity limit, so the cases are drawn that way; asymmetric limits and
out-of-limit starts are checked for invariants in the Rust test instead.

A second table, ruckig_asymmetric_accel.txt (`python3 ... asymmetric`),
covers different accel and decel limits: Ruckig bounds a positive
acceleration by max_acceleration and a negative one by min_acceleration,
which is the planner's rule (accel limit while the speed rises, decel limit
while it falls) for a move that never reverses. So its cases start at rest
or moving forwards, with an acceleration that ends at a forward speed within
the limit, towards targets ahead of where Ruckig's own stop ends. Ruckig has
one jerk, so accel and decel jerks stay equal there.
"""

import sys

import ruckig

from splitmix import SplitMix64, write_table

CASES = 100_000
SEED = 0x5EED_0014


def draw(rng):
    """One case's limits, start state and target recipe (mirrored in Rust)."""
    v = rng.scale(-4, 10)
    a = v * rng.scale(-3, 5)
    j = a * a / v * rng.scale(-2, 7)
    p0 = (2.0 * rng.unit() - 1.0) * 100.0
    kind = rng.below(8)
    if kind == 0:
        v0, a0 = 0.0, 0.0
    else:
        v0 = v * (2.0 * rng.unit() - 1.0)
        a0 = a * (2.0 * rng.unit() - 1.0)
        if kind == 1:
            a0 = 0.0
        for _ in range(60):
            coast = v0 + a0 * abs(a0) / (2.0 * j)
            if -v <= coast <= v:
                break
            a0 *= 0.5
        else:
            a0 = 0.0
    vf = v * rng.unit() if rng.below(4) == 0 else 0.0
    near = rng.below(3) != 0
    k = rng.below(21)
    u = rng.unit()
    side = 1.0 if rng.below(2) == 0 else -1.0
    return v, a, j, p0, v0, a0, vf, near, k, u, side


def solve(inp):
    """Ruckig's trajectory for `inp`, or None where it reports an error."""
    traj = ruckig.Trajectory(1)
    try:
        res = ruckig.Ruckig(1).calculate(inp, traj)
    except ruckig.RuckigError:
        return None
    if res not in (ruckig.Result.Working, ruckig.Result.Finished):
        return None
    return traj


def inputs(p0, v0, a0, v, a, j, d=None):
    inp = ruckig.InputParameter(1)
    inp.current_position = [p0]
    inp.current_velocity = [v0]
    inp.current_acceleration = [a0]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [v]
    inp.max_acceleration = [a]
    if d is not None:
        inp.min_acceleration = [-d]
    inp.max_jerk = [j]
    return inp


def stop_position(p0, v0, a0, v, a, j, d=None):
    """Where Ruckig's own time-optimal stop (velocity interface) ends."""
    inp = inputs(p0, v0, a0, v, a, j, d)
    inp.control_interface = ruckig.ControlInterface.Velocity
    inp.target_velocity = [0.0]
    traj = solve(inp)
    if traj is None:
        return None
    pos, _, _ = traj.at_time(traj.duration)
    return pos[0]


def duration(p0, v0, a0, target, vf_signed, v, a, j, d=None):
    inp = inputs(p0, v0, a0, v, a, j, d)
    inp.target_position = [target]
    inp.target_velocity = [vf_signed]
    traj = solve(inp)
    return None if traj is None else traj.duration


def main():
    rng = SplitMix64(SEED)
    lines = [
        "# Ruckig 0.19.4 durations for planner/tests/state_to_state.rs; written by",
        "# ruckig_state_to_state.py (seed 0x5EED0014): target, final-velocity sign, duration_s",
    ]
    for _ in range(CASES):
        v, a, j, p0, v0, a0, vf, near, k, u, side = draw(rng)
        span = v * v / a + a / j * v
        stop = stop_position(p0, v0, a0, v, a, j)
        if stop is None:
            lines.append("x x x")
            continue
        if vf > 0.0:
            # Far enough beyond the stop for the final speed to be reachable.
            sign = 1.0 if v0 > 0.0 or (v0 == 0.0 and side > 0.0) else -1.0
            target = stop + sign * span * (2.0 + 4.0 * u)
        elif near:
            # Near the stopping point, on either side: 2^-k of the span.
            # Not closer than 2^-16: Ruckig accepts a profile whose end is
            # within 1e-8 of the target.
            target = stop + side * max(span * (1.0 + u) * (2.0 ** (-k)), 2.0**-16)
        else:
            target = p0 + side * span * 8.0 * u
        sign_char = "0"
        vf_signed = 0.0
        if vf > 0.0:
            sign_char = "+" if sign > 0.0 else "-"
            vf_signed = sign * vf
        d = duration(p0, v0, a0, target, vf_signed, v, a, j)
        if d is None:
            lines.append("%r %s x" % (target, sign_char))
        else:
            lines.append("%r %s %.13g" % (target, sign_char, d))
    write_table("ruckig_state_to_state.txt", lines)


ASYMMETRIC_SEED = 0x5EED_A014


def draw_asymmetric(rng):
    """One case of the asymmetric table (mirrored in Rust)."""
    v = rng.scale(-4, 10)
    a = v * rng.scale(-3, 5)
    d = a * rng.scale(-2, 2)
    j = a * a / v * rng.scale(-2, 7)
    p0 = (2.0 * rng.unit() - 1.0) * 100.0
    kind = rng.below(4)
    v0 = 0.0 if kind == 0 else v * rng.unit()
    a0 = 0.0 if kind <= 1 else (a + d) * rng.unit() - d
    for _ in range(60):
        coast = v0 + a0 * abs(a0) / (2.0 * j)
        if 0.0 <= coast <= v:
            break
        a0 *= 0.5
    else:
        a0 = 0.0
    vf = v * rng.unit() if rng.below(4) == 0 else 0.0
    k = rng.below(21)
    u = rng.unit()
    return v, a, d, j, p0, v0, a0, vf, k, u


def main_asymmetric():
    rng = SplitMix64(ASYMMETRIC_SEED)
    lines = [
        "# Ruckig 0.19.4 durations for planner/tests/state_to_state.rs; written by",
        "# ruckig_state_to_state.py asymmetric (seed 0x5EEDA014): target, duration_s",
    ]
    for _ in range(CASES):
        v, a, d, j, p0, v0, a0, vf, k, u = draw_asymmetric(rng)
        span = v * v / min(a, d) + max(a, d) / j * v
        stop = stop_position(p0, v0, a0, v, a, j, d)
        if stop is None:
            lines.append("x x")
            continue
        if vf > 0.0:
            target = stop + span * (2.0 + 4.0 * u)
        else:
            # Ahead of the stop by 2^-k of the span (not closer than 2^-16:
            # Ruckig accepts an end within 1e-8 of the target).
            target = stop + max(span * (1.0 + u) * (2.0 ** (-k)), 2.0**-16)
        dur = duration(p0, v0, a0, target, vf, v, a, j, d)
        lines.append("%r %s" % (target, "x" if dur is None else "%.13g" % dur))
    write_table("ruckig_asymmetric_accel.txt", lines)


if __name__ == "__main__":
    if sys.argv[1:] == ["asymmetric"]:
        main_asymmetric()
    else:
        main()
