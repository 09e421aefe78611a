#!/usr/bin/env python3
"""Writes knife_blade.stl, the blade of the rotary knife.

The blade is a prism: the profile below (metres, in the blade's X-Z plane,
counter-clockwise with X to the right and Z up) is extruded along Y, the
knife's rotation axis. It is a tapered blade 90 mm long from the drum surface
(z = 0) to a 2 mm edge at z = 0.09. Origin: the middle of the blade's root,
so the blade is mounted on the drum surface.

Binary STL, one flat normal per facet, counter-clockwise winding seen from
outside. Run from anywhere: `python3 make_meshes.py` (standard library only;
the prism writer is shared in `scenes/robots/prism_stl.py`).
"""
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from prism_stl import write_prism  # noqa: E402  (scenes/robots/prism_stl.py)

ROOT_HALF_THICKNESS_M = 0.012
EDGE_HALF_THICKNESS_M = 0.001
LENGTH_M = 0.09   # along Z
WIDTH_M = 0.16    # along Y (extrusion)

R, E, L = ROOT_HALF_THICKNESS_M, EDGE_HALF_THICKNESS_M, LENGTH_M
PROFILE = [(-R, 0.0), (R, 0.0), (E, L), (-E, L)]
# The profile is convex around this point: caps are fans from it.
CAP_CENTRE = (0.0, 0.03)


if __name__ == "__main__":
    out = HERE / "meshes" / "knife_blade.stl"
    n = write_prism(out, PROFILE, CAP_CENTRE, WIDTH_M, "rotary knife blade, metres")
    print(f"wrote {out} ({n} triangles)")
