"""What `--save` costs: every shipped scene run with and without a recording.

    python3 tests/recording_overhead.py [TWIN_BINARY] [RUNS]

Runs `twin run SCENE --no-render --trace <tmp>.csv` and the same with
`--save <tmp>.rrd`, RUNS times each (default 5), and prints the best wall
time of each and the difference, absolute and relative. The README's
benchmark table quotes it. Timing only: it asserts nothing.
"""

import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def best(command, runs):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        times.append(time.perf_counter() - start)
    return min(times)


def main(args):
    twin = Path(args[0]) if args else ROOT / "target/debug/twin"
    runs = int(args[1]) if len(args) > 1 else 5
    with tempfile.TemporaryDirectory() as out:
        trace, rrd = str(Path(out) / "t.csv"), str(Path(out) / "t.rrd")
        print(f"{'scene':28s} {'no --save':>10s} {'--save':>10s} {'cost':>10s}")
        for scene in sorted((ROOT / "scenes").glob("*.toml")):
            plain = [str(twin), "run", str(scene), "--no-render", "--trace", trace]
            a = best(plain, runs)
            b = best(plain + ["--save", rrd], runs)
            print(f"{scene.stem:28s} {a:9.3f}s {b:9.3f}s {1000 * (b - a):+7.0f} ms {100 * (b - a) / a:+6.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
