"""Reads recordings back with Rerun's own SDK and checks them against the
run's trace, the default layout, the logs and Rerun's URDF importer.

    python3 tests/recording_matches_trace.py RUN.rrd RUN.csv [RUN.rrd RUN.csv ...]
        [--log RUN.rrd ENTITY TEXT ...] [--urdf RUN.rrd ROBOT.urdf ...]

Needs `rerun-sdk[datafusion]==0.36.3` (`.ci/run` installs it in a venv).

For every pair (a recording and the trace of the same run):

* every trace column but `time_s` and string tags (logged as text) has a
  series in the recording: a line of an entity's `Scalars`, named after
  the column by the entity's `SeriesLines` names (`J1.cmd_pos`,
  `MC1.EN`, `Main.State`);
* each such line equals its trace column at every trace row, reading the
  recording as the viewer does: the latest sample at or before the row's
  `sim_time` (a series is logged where it changes). f64 values must be
  equal bit for bit; REAL tags, which the trace writes at single
  precision, equal at single precision;
* the recording carries a blueprint, and both are under the application id
  `twin`; the recording's id is `<scene>-<unix time in ms>`.

`--log RUN.rrd ENTITY TEXT`: a text log entry at ENTITY of that recording
contains TEXT (a fault with its meaning, say).

`--urdf RUN.rrd ROBOT.urdf`: the robot's link visuals are at the entity
paths, and in the named frames, that Rerun's own URDF importer gives the
same file (`rerun ROBOT.urdf`), so a layout saved for one applies to the
other; the joints' origins are at `tf_static`.

Exit code 0 when all hold, 1 with one line per failure otherwise.
"""

import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import rerun as rr

def first_value(cells):
    """The first non-empty cell of a column (a static component's value)."""
    for v in cells:
        if v is not None and len(v) > 0:
            return v
    return None


def numeric(cells):
    """Whether a trace column holds numbers (a string tag holds text)."""
    for x in cells:
        try:
            float(x)
        except ValueError:
            return False
    return True


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
    # Read as text, header apart: a traced tag may repeat a column's name
    # (`Move.PC` is both the instruction's bit and a `[trace] tags` entry).
    table = pd.read_csv(trace_csv, dtype=str, keep_default_na=False, header=None)
    header = list(table.iloc[0])
    rows_text = table.iloc[1:].reset_index(drop=True)
    by_name = {}
    for k, name in enumerate(header):
        by_name.setdefault(name, []).append(k)
    times_text = rows_text[header.index("time_s")]
    at = np.array([math.floor(float(t) * 1e9 + 0.5) for t in times_text], dtype=np.int64)
    sim_ns = frame["sim_time"].to_numpy().astype("timedelta64[ns]").astype(np.int64)
    compared = set()
    for column in frame.columns:
        if not column.endswith(":Scalars:scalars"):
            continue
        entity = column[: -len(":Scalars:scalars")]
        names_column = f"{entity}:SeriesLines:names"
        names = first_value(frame[names_column]) if names_column in frame.columns else None
        if names is None:
            failures.append(f"{rrd}: {entity} has no SeriesLines names")
            continue
        cells = frame[column]
        rows = [i for i, v in enumerate(cells) if v is not None and len(v) > 0]
        times = sim_ns[rows]
        for k, name in enumerate(names):
            for index in by_name.get(name, []):
                texts = rows_text[index]
                values = np.array([float(cells.iloc[i][k]) for i in rows])
                got = latest_at(times, values, at)
                want = np.array([float(x) for x in texts])
                if entity.lstrip("/").startswith("tags") and any("." in x or "e" in x for x in texts):
                    same = (got.astype(np.float32) == want.astype(np.float32)) | (np.isnan(got) & np.isnan(want))
                else:
                    same = (got == want) | (np.isnan(got) & np.isnan(want))
                if not same.all():
                    j = int(np.argmin(same))
                    failures.append(
                        f"{rrd}: {entity} {name} is {got[j]!r} at t = {times_text[j]} s, the trace's is {want[j]!r}"
                    )
                compared.add(index)
    for index, name in enumerate(header):
        if name == "time_s" or index in compared or not numeric(rows_text[index]):
            continue
        failures.append(f"{rrd}: no series for the trace's {name} (column {index + 1})")
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


def check_log(client, dataset_name, rrd, entity, text):
    """A text log entry at `entity` contains `text`."""
    frame = client.get_dataset(dataset_name).reader(index="sim_time").to_pandas()
    column = f"/{entity.strip('/')}:TextLog:text"
    if column not in frame.columns:
        return [f"{rrd}: no text log at /{entity.strip('/')}"]
    for cells in frame[column]:
        if cells is not None and any(text in str(t) for t in cells):
            return []
    return [f"{rrd}: no entry at /{entity.strip('/')} contains {text!r}"]


def frames_by_entity(frame):
    """Each entity's `CoordinateFrame` (its first value)."""
    out = {}
    for column in frame.columns:
        if column.endswith(":CoordinateFrame:frame"):
            value = first_value(frame[column])
            if value is not None:
                out[column[: -len(":CoordinateFrame:frame")]] = str(value[0])
    return out


def check_urdf(client, dataset_name, rrd, urdf, scratch):
    """The robot's visuals are where, and in the frames, Rerun's URDF importer puts them."""
    imported = scratch / (Path(urdf).stem + ".imported.rrd")
    rec = rr.RecordingStream("twin", recording_id=f"import-{Path(urdf).stem}")
    rec.save(str(imported))
    rec.log_file_from_path(urdf, static=True)
    rec.flush()
    rec.disconnect()
    server = rr.server.Server(datasets={"imported": [str(imported)]})
    imported_client = server.client()
    theirs = frames_by_entity(imported_client.get_dataset("imported").reader(index=None).to_pandas())
    ours = frames_by_entity(client.get_dataset(dataset_name).reader(index=None).to_pandas())
    failures = []
    if not theirs:
        return [f"{urdf}: Rerun's importer logged no frames"]
    for entity, frame in sorted(theirs.items()):
        if "/collision_geometries/" in entity:
            continue
        if entity not in ours:
            failures.append(f"{rrd}: no entity {entity} (Rerun's importer logs {urdf}'s frame {frame!r} there)")
        elif ours[entity] != frame:
            failures.append(f"{rrd}: {entity} is in frame {ours[entity]!r}, Rerun's importer says {frame!r}")
    visuals = [e for e in ours if "/visual_geometries/" in e]
    for entity in visuals:
        if entity not in theirs:
            failures.append(f"{rrd}: {entity} is not an entity Rerun's importer gives {urdf}")
    static = client.get_dataset(dataset_name).reader(index=None).to_pandas()
    if "/tf_static:Transform3D:child_frame" not in static.columns:
        failures.append(f"{rrd}: no joint origins at /tf_static")
    return failures


def main(args):
    logs, urdfs, pairs_args = [], [], []
    i = 0
    while i < len(args):
        if args[i] == "--log" and i + 3 < len(args):
            logs.append(tuple(args[i + 1 : i + 4]))
            i += 4
        elif args[i] == "--urdf" and i + 2 < len(args):
            urdfs.append(tuple(args[i + 1 : i + 3]))
            i += 3
        else:
            pairs_args.append(args[i])
            i += 1
    if len(pairs_args) % 2 or not (pairs_args or logs or urdfs):
        print(__doc__)
        return 2
    failures = []
    pairs = list(zip(pairs_args[::2], pairs_args[1::2]))
    recordings = sorted({rrd for rrd, _ in pairs} | {l[0] for l in logs} | {u[0] for u in urdfs})
    names = {rrd: f"run{k}" for k, rrd in enumerate(recordings)}
    # One server for all recordings (starting one takes seconds).
    server = rr.server.Server(datasets={names[rrd]: [str(Path(rrd))] for rrd in recordings})
    client = server.client()
    for rrd, trace_csv in pairs:
        found, count = check(client, names[rrd], Path(rrd), Path(trace_csv))
        failures += found
        print(f"{rrd}: {count} series equal the trace" if not found else f"{rrd}: {len(found)} failure(s)")
    for rrd, entity, text in logs:
        found = check_log(client, names[rrd], rrd, entity, text)
        failures += found
        print(f"{rrd}: /{entity.strip('/')} says {text!r}" if not found else f"{rrd}: {len(found)} failure(s)")
    if urdfs:
        scratch = Path(tempfile.mkdtemp(prefix="twin-urdf-"))
        for rrd, urdf in urdfs:
            found = check_urdf(client, names[rrd], rrd, urdf, scratch)
            failures += found
            print(f"{rrd}: {urdf}'s visuals and frames as Rerun imports them" if not found else f"{rrd}: {len(found)} failure(s)")
    for line in failures:
        print(line)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
