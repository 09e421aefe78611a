#!/usr/bin/env python3
"""Writes knife_blade.stl, the blade of the rotary knife.

The blade is a prism: the profile below (metres, in the blade's X-Z plane,
counter-clockwise with X to the right and Z up) is extruded along Y, the
knife's rotation axis. It is a tapered blade 90 mm long from the drum surface
(z = 0) to a 2 mm edge at z = 0.09. Origin: the middle of the blade's root,
so the blade is mounted on the drum surface.

Binary STL, one flat normal per facet, counter-clockwise winding seen from
outside. Run from anywhere: `python3 make_meshes.py` (standard library only).
"""
import math
import pathlib
import struct

ROOT_HALF_THICKNESS_M = 0.012
EDGE_HALF_THICKNESS_M = 0.001
LENGTH_M = 0.09   # along Z
WIDTH_M = 0.16    # along Y (extrusion)

R, E, L = ROOT_HALF_THICKNESS_M, EDGE_HALF_THICKNESS_M, LENGTH_M
PROFILE = [(-R, 0.0), (R, 0.0), (E, L), (-E, L)]
# The profile is convex around this point: caps are fans from it.
CAP_CENTRE = (0.0, 0.03)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def unit(v):
    n = math.sqrt(dot(v, v))
    return tuple(x / n for x in v)


def triangles():
    y0, y1 = -WIDTH_M / 2, WIDTH_M / 2
    p3 = lambda p, y: (p[0], y, p[1])  # profile (x, z) at depth y
    tris = []
    n = len(PROFILE)
    for i in range(n):
        a, b = PROFILE[i], PROFILE[(i + 1) % n]
        # A profile counter-clockwise in (x, z) faces -Y (x cross z = -y), so
        # the -Y cap keeps its order and the +Y cap is reversed.
        tris.append((p3(CAP_CENTRE, y1), p3(b, y1), p3(a, y1)))
        tris.append((p3(CAP_CENTRE, y0), p3(a, y0), p3(b, y0)))
        # Side wall of edge a->b: outward is to the right of a->b in (x, z).
        tris.append((p3(a, y0), p3(a, y1), p3(b, y1)))
        tris.append((p3(a, y0), p3(b, y1), p3(b, y0)))
    return tris


def check_outward(tris):
    """Every facet normal points away from the solid (tested at the facet centre)."""
    for t in tris:
        normal = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])))
        centre = tuple(sum(c) / 3 for c in zip(*t))
        inner = (CAP_CENTRE[0], 0.0, CAP_CENTRE[1])
        assert dot(normal, sub(centre, inner)) > 0, (t, normal)


def write_binary_stl(path, tris):
    with open(path, "wb") as f:
        f.write(b"rotary knife blade, metres".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            normal = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])))
            f.write(struct.pack("<3f", *normal))
            for v in t:
                f.write(struct.pack("<3f", *v))
            f.write(struct.pack("<H", 0))


if __name__ == "__main__":
    tris = triangles()
    check_outward(tris)
    out = pathlib.Path(__file__).resolve().parent / "meshes" / "knife_blade.stl"
    out.parent.mkdir(exist_ok=True)
    write_binary_stl(out, tris)
    print(f"wrote {out} ({len(tris)} triangles)")
