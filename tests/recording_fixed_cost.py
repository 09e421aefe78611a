"""What `--save` costs a run whatever its length: the fixed cost.

    python3 tests/recording_fixed_cost.py TWIN [TWIN ...] [--runs N] [--scene S ...]

Runs `twin run SCENE --no-render --duration 0.004` (one coarse update)
with and without `--save <tmp>.rrd`, for every binary given, the runs of
all binaries and both modes interleaved (these machines are shared and
noisy: a slow spell hits every variant alike), N rounds (default 30).
Prints per binary and scene the median and best wall time and CPU time
(user + system) of each mode and their difference: the fixed cost of a
recording. Default scenes: heavy_arm and indexing_table. Timing only: it
asserts nothing; docs/benchmarks.md quotes it.
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def timed(command):
    """Wall and CPU seconds (user + system) of one run."""
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) not in (0, 2, 3, 4, 6):
        raise SystemExit(f"{' '.join(command)}: exit {os.waitstatus_to_exitcode(status)}")
    return wall, usage.ru_utime + usage.ru_stime


def main(args):
    binaries, scenes, runs = [], [], 30
    i = 0
    while i < len(args):
        if args[i] == "--runs":
            runs = int(args[i + 1])
            i += 2
        elif args[i] == "--scene":
            scenes.append(args[i + 1])
            i += 2
        else:
            binaries.append(args[i])
            i += 1
    if not binaries:
        print(__doc__)
        return 2
    scenes = scenes or ["heavy_arm", "indexing_table"]
    samples = {}
    with tempfile.TemporaryDirectory() as out:
        rrd = str(Path(out) / "t.rrd")
        for _ in range(runs):
            for scene in scenes:
                path = str(ROOT / "scenes" / f"{scene}.toml")
                for binary in binaries:
                    plain = [binary, "run", path, "--no-render", "--duration", "0.004"]
                    for mode, command in (("plain", plain), ("save", plain + ["--save", rrd])):
                        samples.setdefault((binary, scene, mode), []).append(timed(command))
    print(f"{'binary':24s} {'scene':16s} {'mode':6s} {'wall med':>9s} {'wall min':>9s} {'cpu med':>9s}")
    for binary in binaries:
        for scene in scenes:
            rows = {}
            for mode in ("plain", "save"):
                walls = [w for w, _ in samples[(binary, scene, mode)]]
                cpus = [c for _, c in samples[(binary, scene, mode)]]
                rows[mode] = (statistics.median(walls), min(walls), statistics.median(cpus))
                w_med, w_min, c_med = rows[mode]
                print(f"{Path(binary).name:24s} {scene:16s} {mode:6s} {1e3 * w_med:7.1f}ms {1e3 * w_min:7.1f}ms {1e3 * c_med:7.1f}ms")
            d = [1e3 * (rows["save"][k] - rows["plain"][k]) for k in range(3)]
            print(f"{Path(binary).name:24s} {scene:16s} {'cost':6s} {d[0]:+7.1f}ms {d[1]:+7.1f}ms {d[2]:+7.1f}ms")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
