#!/usr/bin/env python3
"""quadex and Gmsh side by side on the same drawings, meshed at a target
size H as users of each set it.

quadex: `quadex mesh PART.dxf --size H -o OUT.msh` (the drawing as CAD
writes it).

Gmsh: the same geometry built through its API (OpenCASCADE kernel: lines,
circular arcs, circles), `Mesh.MeshSizeMax = H`, and the quad settings
users try:

- `recombine-simple`: `Mesh.RecombineAll = 1`, `Mesh.Algorithm = 8`
  (Frontal-Delaunay for quads), `Mesh.RecombinationAlgorithm = 0` (simple);
- `recombine-blossom`: the same with `Mesh.RecombinationAlgorithm = 1`
  (Blossom, Gmsh's default);
- `blossom-full-quad`: `Mesh.RecombinationAlgorithm = 3` (full-quad Blossom);
- `subdivision`: the same as `recombine-blossom` with
  `Mesh.SubdivisionAlgorithm = 1` (every element split into quads: all
  quads, at twice the density, the boundary's segments halved).

Every mesh is judged by the benchmark set's `tools/judge.py` against the
mesh's own boundary (its boundary edges chained into a .poly: the judge
checks that every cell is a quad, that every quad is strictly convex, the
edges conform and the quads cover the polygon of the boundary nodes). The
boundary nodes' largest distance to the true curves is measured beside
it. Time: quadex's wall clock as a process (reading the drawing, loading
the model, meshing, writing), Gmsh's `generate(2)` in process.

usage: compare_gmsh_cad.py QUADEX_BINARY OUTDIR

Needs `python3 -m pip install gmsh meshio numpy scipy`.
"""
import math
import os
import subprocess
import sys
import time
from collections import defaultdict

import gmsh
import meshio
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BENCH = os.path.join(ROOT, "..", "shared", "bench")
sys.path.insert(0, os.path.join(BENCH, "tools"))
from judge import evaluate  # noqa: E402

CAD = os.path.join(ROOT, "tests", "data", "cad")


# The true curves, for the boundary nodes' distance to them.
def seg_dist(p, a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    t = np.clip(((p - a) @ d) / (d @ d), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def circle_dist(p, c, r):
    return np.abs(np.linalg.norm(p - np.asarray(c, float), axis=1) - r)


def part_distance(p):
    """The rounded plate, the bolt hole and the slot of part.dxf (the
    circles' full distance is a bound from below on the arcs')."""
    d = [
        seg_dist(p, (10, 0), (90, 0)), seg_dist(p, (100, 10), (100, 50)),
        seg_dist(p, (90, 60), (10, 60)), seg_dist(p, (0, 50), (0, 10)),
        circle_dist(p, (90, 10), 10), circle_dist(p, (90, 50), 10),
        circle_dist(p, (10, 50), 10), circle_dist(p, (10, 10), 10),
        circle_dist(p, (25, 30), 8),
        seg_dist(p, (55, 20), (80, 20)), seg_dist(p, (55, 30), (80, 30)),
        circle_dist(p, (55, 25), 5), circle_dist(p, (80, 25), 5),
    ]
    return np.min(d, axis=0)


def annulus_distance(p):
    return np.minimum(circle_dist(p, (0, 0), 1), circle_dist(p, (0, 0), 2))


def part_exact_area():
    return 100 * 60 - (4 - math.pi) * 100 - math.pi * 64 - (25 * 10 + math.pi * 25)


def build_part():
    occ = gmsh.model.occ
    outer = occ.addRectangle(0, 0, 0, 100, 60, roundedRadius=10)
    bolt = occ.addDisk(25, 30, 0, 8, 8)
    slot_box = occ.addRectangle(55, 20, 0, 25, 10)
    ends = [occ.addDisk(55, 25, 0, 5, 5), occ.addDisk(80, 25, 0, 5, 5)]
    slot, _ = occ.fuse([(2, slot_box)], [(2, e) for e in ends])
    occ.cut([(2, outer)], [(2, bolt)] + slot)
    occ.synchronize()


def build_annulus():
    occ = gmsh.model.occ
    outer = occ.addDisk(0, 0, 0, 2, 2)
    inner = occ.addDisk(0, 0, 0, 1, 1)
    occ.cut([(2, outer)], [(2, inner)])
    occ.synchronize()


CASES = [
    ("part", os.path.join(CAD, "part.dxf"), build_part, part_distance, 100.0, [4.0, 2.0]),
    ("annulus", os.path.join(CAD, "annulus.dxf"), build_annulus, annulus_distance, 4.0, [0.2, 0.1]),
]

GMSH_SETTINGS = [
    ("recombine-simple", {"Mesh.RecombineAll": 1, "Mesh.Algorithm": 8,
                          "Mesh.RecombinationAlgorithm": 0}),
    ("recombine-blossom", {"Mesh.RecombineAll": 1, "Mesh.Algorithm": 8,
                           "Mesh.RecombinationAlgorithm": 1}),
    ("blossom-full-quad", {"Mesh.RecombineAll": 1, "Mesh.Algorithm": 8,
                           "Mesh.RecombinationAlgorithm": 3}),
    ("subdivision", {"Mesh.RecombineAll": 1, "Mesh.Algorithm": 8,
                     "Mesh.RecombinationAlgorithm": 1, "Mesh.SubdivisionAlgorithm": 1}),
]


def boundary_poly(mesh_path, poly_path):
    """Writes the mesh's boundary (edges of one 2D cell) as a .poly; returns
    the boundary node coordinates."""
    m = meshio.read(mesh_path)
    pts = np.asarray(m.points)[:, :2]
    count = defaultdict(int)
    for cb in m.cells:
        if cb.type in ("quad", "triangle"):
            for c in np.asarray(cb.data):
                for k in range(len(c)):
                    a, b = int(c[k]), int(c[(k + 1) % len(c)])
                    count[(min(a, b), max(a, b))] += 1
    # Chain the boundary edges into loops (the judge's reader follows each
    # segment's end to the next segment's start).
    adj = defaultdict(list)
    for (a, b), c in count.items():
        if c == 1:
            adj[a].append(b)
            adj[b].append(a)
    edges, seen = [], set()
    for start in sorted(adj):
        if start in seen:
            continue
        prev, cur = None, start
        while cur not in seen:
            seen.add(cur)
            nxt = adj[cur][0] if adj[cur][0] != prev else adj[cur][1]
            edges.append((cur, nxt))
            prev, cur = cur, nxt
    nodes = sorted(seen)
    index = {v: i + 1 for i, v in enumerate(nodes)}
    with open(poly_path, "w") as f:
        f.write(f"{len(nodes)} 2 0 0\n")
        for v in nodes:
            f.write(f"{index[v]} {float(pts[v][0])!r} {float(pts[v][1])!r}\n")
        f.write(f"{len(edges)} 0\n")
        for k, (a, b) in enumerate(edges):
            f.write(f"{k + 1} {index[a]} {index[b]}\n")
        f.write("0\n")
    return pts[nodes]


def judged(mesh_path, poly_path, distance, scale):
    bnodes = boundary_poly(mesh_path, poly_path)
    r = evaluate(poly_path, mesh_path)
    r["boundary_nodes"] = len(bnodes)
    r["off_curve"] = float(distance(bnodes).max()) / scale
    return r


def run_quadex(binary, dxf, h, out):
    t0 = time.perf_counter()
    subprocess.run([binary, "mesh", dxf, "--size", str(h), "-o", out, "--threads", "1"],
                   check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def run_gmsh(build, h, settings, out):
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("case")
    build()
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    for k, v in settings.items():
        gmsh.option.setNumber(k, v)
    t0 = time.perf_counter()
    try:
        gmsh.model.mesh.generate(2)
        seconds = time.perf_counter() - t0
        gmsh.write(out)
        error = None
    except Exception as e:  # Gmsh raises on a failed meshing
        seconds, error = time.perf_counter() - t0, str(e)
    gmsh.finalize()
    return seconds, error


def row(case, h, tool, seconds, r):
    if r is None:
        return f"| {case} | {h} | {tool} | failed | | | | | | |"
    irr = 100.0 * r["irregular_interior"] / max(r["interior_nodes"], 1)
    if r["valid"]:
        valid = "yes"
    elif any(x.startswith("non-quad cells") for x in r["reasons"]):
        # The other reasons follow from the triangles (their edges are
        # not counted as the quads' boundary).
        valid = "**no**: " + next(x for x in r["reasons"] if x.startswith("non-quad cells"))
    else:
        valid = "**no**: " + "; ".join(r["reasons"])
    return (f"| {case} | {h} | {tool} | {valid} | {r.get('quads', 0)} | "
            f"{r.get('boundary_nodes', 0)} | {r.get('sj_min', float('nan')):.3f} | "
            f"{r.get('sj_mean', float('nan')):.3f} | {irr:.1f} % | {seconds:.3f} |")


def main():
    binary, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    print("| part | H | mesher | valid (judge.py) | quads | boundary nodes | SJ min | SJ mean | "
          "irregular | time (s) |")
    print("|---|---:|---|---|---:|---:|---:|---:|---:|---:|")
    worst_off = 0.0
    for case, dxf, build, distance, scale, sizes in CASES:
        for h in sizes:
            path = os.path.join(out, f"{case}_{h}_quadex.msh")
            seconds = run_quadex(binary, dxf, h, path)
            r = judged(path, path[:-4] + ".poly", distance, scale)
            worst_off = max(worst_off, r["off_curve"])
            print(row(case, h, "quadex", seconds, r))
            for name, settings in GMSH_SETTINGS:
                path = os.path.join(out, f"{case}_{h}_{name}.msh")
                seconds, error = run_gmsh(build, h, settings, path)
                r = None if error else judged(path, path[:-4] + ".poly", distance, scale)
                print(row(case, h, f"Gmsh {name}", seconds, r))
    print(f"\nquadex's boundary nodes lie within {worst_off:.1e} of the part's size of the "
          "true curves.")


if __name__ == "__main__":
    main()
