#!/usr/bin/env python3
"""Reference values for the MCCP clamped-spline oracle test (tests.rs).

Run once from this directory:  python3 oracle.py > oracle.csv
Needs numpy and scipy (made with numpy 2.4.6, scipy 1.17.1). Each all-cubic cam
is interpolated with scipy.interpolate.CubicSpline(bc_type=((1, start_slope),
(1, end_slope))) — a clamped spline computed independently of the Rust code —
and sampled with its value, first and second derivative at 1001 master points.

Lines:  cam,<id>,<start_slope>,<end_slope>,<x>:<y>;<x>:<y>;...
        pt,<id>,<master>,<slave>,<slope>,<curvature>
Floats are written with repr() (shortest round-trip form).
"""
import numpy as np
from scipy.interpolate import CubicSpline

CAMS = [
    (1.0, -2.0, [(0, 0), (10, 30), (20, 35), (30, 30), (40, 0)]),
    (0.5, 3.0, [(0, 0), (1.5, 2.0), (4, -1.0), (4.5, -0.25), (7, 3.5), (10, 3.0),
                (11, 1.0), (15, 8.0), (16.25, 7.5), (20, 12.0), (21, 11.0), (25, 20.0)]),
    (-1.0, 1.0, [(-5, 2.0), (0.3, -1.0), (6, 4.0)]),
    (2.0, -1.0, [(100, 10.0), (160, 40.0)]),
    (-0.75, 0.25, [(0, 0), (30, 10), (60, 50), (90, 120), (120, 200), (150, 270),
                   (180, 310), (210, 330), (240, 335), (270, 340), (300, 350), (330, 355), (360, 360)]),
]

for cid, (s0, s1, pts) in enumerate(CAMS):
    x = np.array([p[0] for p in pts], dtype=float)
    y = np.array([p[1] for p in pts], dtype=float)
    print("cam,%d,%r,%r,%s" % (cid, s0, s1, ";".join("%r:%r" % (float(a), float(b)) for a, b in zip(x, y))))
    cs = CubicSpline(x, y, bc_type=((1, s0), (1, s1)))
    for m in np.linspace(x[0], x[-1], 1001):
        m = float(m)
        print("pt,%d,%r,%r,%r,%r" % (cid, m, float(cs(m)), float(cs(m, 1)), float(cs(m, 2))))
