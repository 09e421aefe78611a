#!/usr/bin/env python3
"""Writes vblock_fixture.stl, the V-block fixture of the indexing table.

A V-block is a prism: the profile below (metres, in the fixture's X-Z plane,
counter-clockwise with X to the right and Z up) is extruded along Y. The notch is a 90-degree V, 30 mm deep, along the Y axis.
Origin: centre of the bottom face, so the block sits on its mounting frame.

Binary STL, one flat normal per facet, counter-clockwise winding seen from
outside. Run from anywhere: `python3 make_meshes.py` (standard library only;
the prism writer is shared in `scenes/robots/prism_stl.py`).
"""
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from prism_stl import write_prism  # noqa: E402  (scenes/robots/prism_stl.py)

WIDTH_M = 0.12   # along X
DEPTH_M = 0.10   # along Y (extrusion)
HEIGHT_M = 0.08  # along Z
NOTCH_HALF_WIDTH_M = 0.03
NOTCH_DEPTH_M = 0.03

# Closed profile in (x, z), counter-clockwise with x to the right and z up.
W, H, N, D = WIDTH_M / 2, HEIGHT_M, NOTCH_HALF_WIDTH_M, NOTCH_DEPTH_M
PROFILE = [(-W, 0.0), (W, 0.0), (W, H), (N, H), (0.0, H - D), (-N, H), (-W, H)]
# The profile is star-shaped around this point: caps are fans from it.
CAP_CENTRE = (0.0, 0.02)


if __name__ == "__main__":
    out = HERE / "meshes" / "vblock_fixture.stl"
    n = write_prism(out, PROFILE, CAP_CENTRE, DEPTH_M, "indexing table V-block fixture, metres")
    print(f"wrote {out} ({n} triangles)")
