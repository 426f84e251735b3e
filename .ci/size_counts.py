#!/usr/bin/env python3
"""How closely quadex's and Gmsh's quad counts follow the boundary's spacing.

For each case the count a mesh of the boundary's size field would have,
the integral of 1/h(x)^2 over the domain, is computed for two ways of
giving a boundary node its size:

- `mean`: the mean of its two segments (quadex's size field,
  `src/extract/size.rs`);
- `min`: the shorter of its two segments.

Inside, h is interpolated linearly over a Delaunay triangulation of the
boundary nodes (nearest node outside their hull), and the integral is taken
over the quads of quadex's own mesh (one point per quad). It is an
estimate: quadex's field also caps its growth with distance and is
constrained to the boundary, which matters only on strongly graded or
non-convex domains.

usage: size_counts.py SWEEP_DIR [--gmsh GMSH_DIR]

SWEEP_DIR is a `.ci/sweep.py` output (summary.json and CASE.msh), GMSH_DIR
a `.ci/gmsh_compare.py` output (gmsh_summary.json). Needs meshio, numpy,
scipy.
"""
import argparse
import contextlib
import io
import json
import os
import statistics
import sys

import meshio
import numpy as np
from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(HERE, "..", "..", "shared", "bench")
sys.path.insert(0, os.path.join(BENCH, "tools"))
from polyio import read_poly  # noqa: E402


def find_case(name):
    for d in ("boundaries", "peer", "edge"):
        p = os.path.join(BENCH, d, name + ".poly")
        if os.path.exists(p):
            return p
    return None


def node_sizes(poly, rule):
    pts, loops, _holes, _segs = read_poly(poly)
    pts = np.asarray(pts, dtype=float)[:, :2]
    at, size = [], []
    for loop in loops:
        n = len(loop)
        for k in range(n):
            a, v, b = pts[loop[k - 1]], pts[loop[k]], pts[loop[(k + 1) % n]]
            la, lb = np.linalg.norm(v - a), np.linalg.norm(b - v)
            at.append(v)
            size.append(0.5 * (la + lb) if rule == "mean" else min(la, lb))
    return np.asarray(at), np.asarray(size)


def field_count(poly, msh, rule):
    at, size = node_sizes(poly, rule)
    lin, near = LinearNDInterpolator(at, size), NearestNDInterpolator(at, size)
    with contextlib.redirect_stdout(io.StringIO()):
        m = meshio.read(msh)
    x = m.points[:, :2][m.cells_dict["quad"]]
    area = 0.5 * np.abs(
        (x[:, 0, 0] - x[:, 2, 0]) * (x[:, 1, 1] - x[:, 3, 1])
        - (x[:, 1, 0] - x[:, 3, 0]) * (x[:, 0, 1] - x[:, 2, 1])
    )
    c = x.mean(axis=1)
    h = lin(c)
    h = np.where(np.isnan(h), near(c), h)
    return float(np.sum(area / h**2))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("sweep")
    ap.add_argument("--gmsh")
    a = ap.parse_args()
    ours = {r["case"]: r for r in json.load(open(os.path.join(a.sweep, "summary.json")))}
    gmsh = {}
    if a.gmsh:
        for r in json.load(open(os.path.join(a.gmsh, "gmsh_summary.json"))):
            if r.get("valid"):
                gmsh[r["case"]] = r["quads"]
    print(f"{'case':28s} | {'quadex':>7s} {'/mean':>6s} {'/min':>6s} | {'Gmsh':>7s} {'/mean':>6s} {'/min':>6s}")
    ratios = {"quadex/mean": [], "quadex/min": [], "gmsh/mean": [], "gmsh/min": []}
    for case in sorted(ours):
        row = ours[case]
        poly, msh = find_case(case), os.path.join(a.sweep, case + ".msh")
        if not row.get("valid") or poly is None or not os.path.exists(msh):
            continue
        fm, fn = field_count(poly, msh, "mean"), field_count(poly, msh, "min")
        q = row["quads"]
        ratios["quadex/mean"].append(q / fm)
        ratios["quadex/min"].append(q / fn)
        line = f"{case:28s} | {q:7d} {q / fm:6.2f} {q / fn:6.2f} |"
        if case in gmsh:
            g = gmsh[case]
            ratios["gmsh/mean"].append(g / fm)
            ratios["gmsh/min"].append(g / fn)
            line += f" {g:7d} {g / fm:6.2f} {g / fn:6.2f}"
        print(line)
    print()
    for k, v in ratios.items():
        if v:
            within = sum(abs(r - 1) <= 0.1 for r in v)
            print(f"{k:12s}: median {statistics.median(v):.3f}, within 10 % in {within} of {len(v)}")


if __name__ == "__main__":
    main()
