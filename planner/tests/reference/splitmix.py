"""What the reference generators share: the SplitMix64 stream they draw
their cases from, which planner/tests/state_to_state.rs repeats bit for bit
(only +, -, *, / and sqrt on the drawn values, which IEEE 754 rounds the same
in both languages), and the writing of a table next to this file.
"""

import os
import sys

MASK = (1 << 64) - 1


def write_table(name, lines):
    """Writes `lines` to the table `name` in this folder."""
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", out, file=sys.stderr)


class SplitMix64:
    def __init__(self, seed):
        self.state = seed & MASK

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    def unit(self):
        """Uniform in [0, 1)."""
        return (self.next() >> 11) * (1.0 / 9007199254740992.0)

    def below(self, n):
        return self.next() % n

    def scale(self, lo, hi):
        """(1 + u) * 2^k, k uniform in lo..=hi: log-uniform-ish, exact."""
        k = lo + self.below(hi - lo + 1)
        return (1.0 + self.unit()) * (2.0**k)
