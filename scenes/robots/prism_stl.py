"""Prism meshes for the scene robots: a closed profile extruded into a binary STL.

Used by the robots' `make_meshes.py` scripts (standard library only). The
profile is given in the part's X-Z plane, counter-clockwise with X to the
right and Z up, and must be star-shaped around `cap_centre` (the caps are
fans from it); it is extruded along Y, centred on y = 0. One flat normal per
facet, counter-clockwise winding seen from outside (checked before writing).
"""
import math
import struct


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def unit(v):
    n = math.sqrt(dot(v, v))
    return tuple(x / n for x in v)


def prism_triangles(profile, cap_centre, extrusion_m):
    """Triangles of `profile` (list of (x, z)) extruded over y in ±extrusion_m / 2."""
    y0, y1 = -extrusion_m / 2, extrusion_m / 2
    p3 = lambda p, y: (p[0], y, p[1])  # profile (x, z) at depth y
    tris = []
    n = len(profile)
    for i in range(n):
        a, b = profile[i], profile[(i + 1) % n]
        # A profile counter-clockwise in (x, z) faces -Y (x cross z = -y), so
        # the -Y cap keeps its order and the +Y cap is reversed.
        tris.append((p3(cap_centre, y1), p3(b, y1), p3(a, y1)))
        tris.append((p3(cap_centre, y0), p3(a, y0), p3(b, y0)))
        # Side wall of edge a->b: outward is to the right of a->b in (x, z).
        tris.append((p3(a, y0), p3(a, y1), p3(b, y1)))
        tris.append((p3(a, y0), p3(b, y1), p3(b, y0)))
    return tris


def check_outward(tris, cap_centre):
    """Every facet normal points away from the solid (tested at the facet centre)."""
    inner = (cap_centre[0], 0.0, cap_centre[1])
    for t in tris:
        normal = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])))
        centre = tuple(sum(c) / 3 for c in zip(*t))
        # Star-shaped solid: the normal points away from the inner axis point.
        assert dot(normal, sub(centre, inner)) > 0, (t, normal)


def write_binary_stl(path, tris, header):
    with open(path, "wb") as f:
        f.write(header.encode("ascii").ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            normal = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])))
            f.write(struct.pack("<3f", *normal))
            for v in t:
                f.write(struct.pack("<3f", *v))
            f.write(struct.pack("<H", 0))


def write_prism(path, profile, cap_centre, extrusion_m, header):
    """Checks and writes the prism; returns the triangle count."""
    tris = prism_triangles(profile, cap_centre, extrusion_m)
    check_outward(tris, cap_centre)
    path.parent.mkdir(exist_ok=True)
    write_binary_stl(path, tris, header)
    return len(tris)
