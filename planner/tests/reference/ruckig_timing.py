"""Times Ruckig on the first 10,000 cases of ruckig_state_to_state.txt, the
cases the planner's `s_curve_plan_state_to_state_ruckig_table_10k`
benchmark plans, so the two planning times compare on one machine:

    pip install ruckig==0.19.4
    python3 planner/tests/reference/ruckig_timing.py
    cargo bench -p planner --bench profiles -- state_to_state

Dev-time only, like the table generator. Ruckig is called through its
Python binding (`Ruckig(1).calculate(input, trajectory)`, inputs built
beforehand), the call's overhead included, as the planner's benchmark
figures were first compared. Mean: the whole set timed, best of 5 runs,
divided by the cases. Worst: each case timed alone in each of 20 passes
over the set, its best time kept (so a preempted run does not count), then
the slowest case. Cases where Ruckig reports an error (`x` in the table)
are left out of both.
"""

import os
import time

import ruckig

from ruckig_state_to_state import SEED, draw, inputs
from splitmix import SplitMix64

CASES = 10_000


def cases():
    """Ruckig's inputs for the table's first CASES cases it solved."""
    table = os.path.join(os.path.dirname(os.path.abspath(__file__)), "ruckig_state_to_state.txt")
    with open(table) as f:
        lines = [line.split() for line in f if not line.startswith("#")][:CASES]
    rng = SplitMix64(SEED)
    out = []
    for target, sign, duration in lines:
        v, a, j, p0, v0, a0, vf, *_ = draw(rng)
        if duration == "x":
            continue
        inp = inputs(p0, v0, a0, v, a, j)
        inp.target_position = [float(target)]
        inp.target_velocity = [{"+": vf, "-": -vf}.get(sign, 0.0)]
        out.append(inp)
    return out


def main():
    inps = cases()
    otg = ruckig.Ruckig(1)
    traj = ruckig.Trajectory(1)
    mean_ns = float("inf")
    for _ in range(5):
        t = time.perf_counter_ns()
        for inp in inps:
            otg.calculate(inp, traj)
        mean_ns = min(mean_ns, (time.perf_counter_ns() - t) / len(inps))
    best = [float("inf")] * len(inps)
    for _ in range(20):
        for i, inp in enumerate(inps):
            best[i] = min(best[i], _timed(otg, inp, traj))
    worst_ns = max(best)
    print(f"Ruckig on {len(inps)} cases: mean {mean_ns:.0f} ns, worst {worst_ns} ns "
          "(through Python, call overhead included)")


def _timed(otg, inp, traj):
    t = time.perf_counter_ns()
    otg.calculate(inp, traj)
    return time.perf_counter_ns() - t


if __name__ == "__main__":
    main()
