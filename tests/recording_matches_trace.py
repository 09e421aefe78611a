"""Reads recordings back with Rerun's own SDK and checks them against the
run's trace and the default layout.

    python3 tests/recording_matches_trace.py RUN.rrd RUN.csv [RUN.rrd RUN.csv ...]

Needs `rerun-sdk[datafusion]==0.36.3` (`.ci/run` installs it in a venv).

For every pair (a recording and the trace of the same run):

* every scalar series of the recording that the trace also has — axes'
  `cmd_pos`, `act_pos`, `cmd_vel`, `torque`; instruction bits and codes;
  traced tags; clearances — equals the trace column at every trace row,
  reading the recording as the viewer does: the latest sample at or before
  the row's `sim_time` (a series is logged where it changes). f64 values
  must be equal bit for bit; REAL tags, which the trace writes at single
  precision, equal at single precision;
* every axis of the trace has its position and velocity series;
* the recording carries a blueprint, and both are under the application id
  `twin`; the recording's id is `<scene>-<unix time in ms>`.

Exit code 0 when all hold, 1 with one line per failure otherwise.
"""

import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import rerun as rr

FB_BITS = {"Done", "Busy", "Active", "CommandAborted", "Error", "ErrorID"}
CONTROL_BITS = {"EN", "DN", "ER", "IP", "AC", "PC", "ACCEL", "DECEL", "ERR", "EXERR", "SEGMENT"}


def unescape(part):
    """An entity-path part as written by the twin (Rerun escapes with `\\`)."""
    return re.sub(r"\\(.)", r"\1", part)


def trace_column(entity):
    """The trace column a recording series equals, or None."""
    parts = [unescape(p) for p in re.findall(r"(?:\\.|[^/])+", entity)]
    if len(parts) == 3 and parts[0] == "axes" and parts[2] in ("cmd_pos", "act_pos", "cmd_vel", "torque"):
        return f"{parts[1]}.{parts[2]}"
    if len(parts) == 3 and parts[0] == "instructions" and parts[2] in FB_BITS | CONTROL_BITS:
        return f"{parts[1]}.{parts[2]}"
    if len(parts) == 2 and parts[0] == "tags":
        return parts[1]
    if len(parts) == 3 and parts[0] == "collisions" and parts[1] == "clearance":
        return f"{parts[2]}.clearance_m"
    return None


def latest_at(times, values, at):
    """The value at or before each of `at` (NaN before the first sample)."""
    order = np.argsort(times, kind="stable")
    times, values = times[order], values[order]
    index = np.searchsorted(times, at, side="right") - 1
    out = np.full(len(at), np.nan)
    ok = index >= 0
    out[ok] = values[index[ok]]
    return out


def check(client, dataset_name, rrd, trace_csv):
    failures = []
    dataset = client.get_dataset(dataset_name)
    frame = dataset.reader(index="sim_time").to_pandas()
    trace = pd.read_csv(trace_csv, dtype=str)
    at = np.array([math.floor(float(t) * 1e9 + 0.5) for t in trace["time_s"]], dtype=np.int64)
    sim_ns = frame["sim_time"].to_numpy().astype("timedelta64[ns]").astype(np.int64)
    compared = set()
    for column in frame.columns:
        if not column.endswith(":Scalars:scalars"):
            continue
        entity = column[: -len(":Scalars:scalars")].lstrip("/")
        name = trace_column(entity)
        if name is None or name not in trace.columns:
            continue
        cells = frame[column]
        rows = [i for i, v in enumerate(cells) if v is not None and len(v) > 0]
        times = sim_ns[rows]
        values = np.array([float(cells.iloc[i][0]) for i in rows])
        got = latest_at(times, values, at)
        want = np.array([float(x) for x in trace[name]])
        if entity.startswith("tags/") and any("." in x or "e" in x for x in trace[name]):
            same = (got.astype(np.float32) == want.astype(np.float32)) | (np.isnan(got) & np.isnan(want))
        else:
            same = (got == want) | (np.isnan(got) & np.isnan(want))
        if not same.all():
            k = int(np.argmin(same))
            failures.append(f"{rrd}: {entity} is {got[k]!r} at t = {trace['time_s'][k]} s, the trace's {name} is {want[k]!r}")
        compared.add(name)
    for name in trace.columns:
        if name.endswith((".cmd_pos", ".act_pos", ".cmd_vel")) and name not in compared:
            failures.append(f"{rrd}: no series for the trace's {name}")
    printed = subprocess.run(
        [str(Path(sys.executable).parent / "rerun"), "rrd", "print", "-v", str(rrd)],
        capture_output=True,
        text=True,
        check=False,
    ).stdout
    if not re.search(r'StoreId\(\s*Blueprint,\s*"twin"', printed) or "ViewportBlueprint" not in printed:
        failures.append(f"{rrd}: no blueprint for the application `twin` in the recording")
    recording = re.search(r'StoreId\(\s*Recording,\s*"([^"]*)",\s*"([^"]*)"', printed)
    if not recording or recording.group(1) != "twin":
        failures.append(f"{rrd}: the recording's application id is not `twin`")
    elif not re.fullmatch(r".+-\d+", recording.group(2)):
        failures.append(f"{rrd}: recording id {recording.group(2)!r} is not <scene>-<unix ms>")
    return failures, len(compared)


def main(args):
    if len(args) == 0 or len(args) % 2:
        print(__doc__)
        return 2
    failures = []
    pairs = list(zip(args[::2], args[1::2]))
    # One server for all recordings (starting one takes seconds).
    server = rr.server.Server(datasets={f"run{i}": [str(Path(rrd))] for i, (rrd, _) in enumerate(pairs)})
    client = server.client()
    for i, (rrd, trace_csv) in enumerate(pairs):
        found, count = check(client, f"run{i}", Path(rrd), Path(trace_csv))
        failures += found
        print(f"{rrd}: {count} series equal the trace" if not found else f"{rrd}: {len(found)} failure(s)")
    for line in failures:
        print(line)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
