#!/usr/bin/env python3
"""Writes the heavy arm's two cast links as prisms (metres, binary STL).

* upper_arm.stl: the upper arm, tapered from 140 mm at the shoulder (z = 0,
  the j2 axis) to 100 mm at the elbow (z = 0.45, the j3 axis), with 50 mm
  of boss beyond each axis; extruded 120 mm along Y (the j2 and j3 axes).
* forearm.stl: the forearm from 50 mm behind the elbow (x = 0, the j3
  axis) to the wrist flange at x = 0.42, tapered from 100 mm to 70 mm;
  extruded 100 mm along Y.

Each profile is in the link's X-Z plane, counter-clockwise with X to the
right and Z up, and convex around its cap centre. Run from anywhere:
`python3 make_meshes.py` (standard library only; the prism writer is
shared in `scenes/robots/prism_stl.py`).
"""
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from prism_stl import write_prism  # noqa: E402  (scenes/robots/prism_stl.py)

UPPER_ARM = [(-0.07, -0.05), (0.07, -0.05), (0.05, 0.5), (-0.05, 0.5)]
UPPER_ARM_CAP = (0.0, 0.225)
FOREARM = [(-0.05, -0.05), (0.42, -0.035), (0.42, 0.035), (-0.05, 0.05)]
FOREARM_CAP = (0.18, 0.0)

if __name__ == "__main__":
    for name, profile, cap, width in [
        ("upper_arm", UPPER_ARM, UPPER_ARM_CAP, 0.12),
        ("forearm", FOREARM, FOREARM_CAP, 0.10),
    ]:
        out = HERE / "meshes" / f"{name}.stl"
        n = write_prism(out, profile, cap, width, f"heavy arm {name}, metres")
        print(f"wrote {out} ({n} triangles)")
