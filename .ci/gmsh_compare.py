#!/usr/bin/env python3
"""Meshes benchmark boundaries with Gmsh (Frontal-Delaunay for quads and
Blossom recombination, `fdq-blossom`), the boundary nodes kept as given (one
transfinite point per segment end, so Gmsh adds no boundary node), judges
each mesh with the bench's judge.py, and, given a sweep.py summary, prints
both side by side.

usage: gmsh_compare.py OUTDIR [--quadex SUMMARY.json] [--cases DIR_OR_FILE ...]

Needs `python3 -m pip install gmsh meshio numpy scipy`.
"""
import argparse
import json
import os
import statistics
import sys
import time

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(HERE, "..", "..", "shared", "bench")
sys.path.insert(0, os.path.join(BENCH, "tools"))
from judge import evaluate  # noqa: E402
from polyio import read_poly  # noqa: E402


def default_cases():
    out = []
    for d in ("boundaries", "peer", "edge"):
        for f in sorted(os.listdir(os.path.join(BENCH, d))):
            if f.endswith(".poly") and f not in ("disk1600.poly", "disk6400.poly"):
                out.append(os.path.join(BENCH, d, f))
    return out


def mesh_with_gmsh(poly, msh):
    pts, loops, _holes, _segs = read_poly(poly)
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("case")
    geo = gmsh.model.geo
    tags = {}
    curve_loops = []
    # The loop with the largest area is the outer one.
    def area(l):
        return 0.5 * sum(pts[l[k]][0] * pts[l[(k + 1) % len(l)]][1] -
                         pts[l[(k + 1) % len(l)]][0] * pts[l[k]][1] for k in range(len(l)))
    order = sorted(range(len(loops)), key=lambda i: -abs(area(loops[i])))
    for i in order:
        l = loops[i]
        for v in l:
            if v not in tags:
                tags[v] = geo.addPoint(float(pts[v][0]), float(pts[v][1]), 0.0)
        lines = []
        for k in range(len(l)):
            a, b = l[k], l[(k + 1) % len(l)]
            lines.append(geo.addLine(tags[a], tags[b]))
        curve_loops.append(geo.addCurveLoop(lines))
    surf = geo.addPlaneSurface(curve_loops)
    geo.synchronize()
    for (_dim, tag) in gmsh.model.getEntities(1):
        gmsh.model.mesh.setTransfiniteCurve(tag, 2)
    gmsh.model.mesh.setRecombine(2, surf)
    gmsh.option.setNumber("Mesh.Algorithm", 8)  # Frontal-Delaunay for quads
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)  # Blossom
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    t0 = time.time()
    err = ""
    try:
        gmsh.model.mesh.generate(2)
        gmsh.write(msh)
    except Exception as e:
        err = str(e)
    secs = time.time() - t0
    gmsh.finalize()
    return secs, err


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--quadex")
    ap.add_argument("--cases", nargs="*")
    a = ap.parse_args()
    cases = []
    for c in a.cases or []:
        if os.path.isdir(c):
            cases += sorted(os.path.join(c, f) for f in os.listdir(c) if f.endswith(".poly"))
        else:
            cases.append(c)
    cases = cases or default_cases()
    os.makedirs(a.outdir, exist_ok=True)
    ours = {}
    if a.quadex:
        ours = {r["case"]: r for r in json.load(open(a.quadex))}
    rows = []
    for poly in cases:
        name = os.path.basename(poly).rsplit(".", 1)[0]
        msh = os.path.join(a.outdir, name + ".msh")
        if os.path.exists(msh):
            os.remove(msh)
        secs, err = mesh_with_gmsh(poly, msh)
        row = {"case": name, "seconds": round(secs, 3), "error": err}
        if not err and os.path.exists(msh):
            try:
                row.update(evaluate(poly, msh))
            except Exception as e:
                row["error"] = f"judge: {e}"
        rows.append(row)
    json.dump(rows, open(os.path.join(a.outdir, "gmsh_summary.json"), "w"), indent=1)

    def irr(r):
        return r["irregular_interior"] / max(r["interior_nodes"], 1)

    print(f"{'case':28} | {'gmsh quads':>10} {'sjmean':>6} {'irr%':>5} {'secs':>5} | "
          f"{'ours quads':>10} {'sjmean':>6} {'irr%':>5} {'secs':>5} | better")
    both, better_sj, better_irr, better_both, good_both = 0, 0, 0, 0, 0
    ratios = []
    md = ["| case | Gmsh quads | Gmsh SJ mean | Gmsh irregular % | quadex quads | quadex SJ mean "
          "| quadex irregular % | quadex vs Gmsh |", "|---|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        o = ours.get(r["case"], {})
        g_ok = r.get("valid")
        o_ok = o.get("valid")
        gs = (f"{r['quads']:10d} {r['sj_mean']:6.3f} {100 * irr(r):5.1f} {r['seconds']:5.2f}"
              if g_ok else f"{'invalid: ' + (r.get('error') or '; '.join(r.get('reasons', [])))[:30]:>30}")
        os_ = (f"{o['quads']:10d} {o['sj_mean']:6.3f} {100 * irr(o):5.1f} {o['seconds']:5.2f}"
               if o_ok else f"{'-':>30}")
        verdict = ""
        if g_ok and o_ok:
            both += 1
            # Figures as the judge rounds them: within 5e-4 (SJ) or 0.05
            # points (irregular share) is a tie.
            s = o["sj_mean"] > r["sj_mean"] + 5e-4
            s_tie = abs(o["sj_mean"] - r["sj_mean"]) <= 5e-4
            i = irr(o) < irr(r) - 5e-4
            i_tie = abs(irr(o) - irr(r)) <= 5e-4
            better_sj += s
            better_irr += i
            better_both += s and i
            good_both += (s or s_tie) and (i or i_tie)
            ratios.append(o["quads"] / r["quads"])
            word = lambda win, tie, name: f"{name} better" if win else (f"{name} equal" if tie else f"{name} worse")
            verdict = word(s, s_tie, "SJ") + ", " + word(i, i_tie, "irregular")
        print(f"{r['case']:28} | {gs} | {os_} | {verdict}")
        cell = lambda x, ok: (f"{x['quads']} | {x['sj_mean']:.3f} | {100 * irr(x):.1f}" if ok
                              else "invalid | | ")
        md.append(f"| {r['case']} | {cell(r, g_ok)} | {cell(o, o_ok)} | {verdict} |")
    with open(os.path.join(a.outdir, "comparison.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    g_valid = [r for r in rows if r.get("valid")]
    print(f"\nGmsh valid on {len(g_valid)} of {len(rows)}.")
    if g_valid:
        print(f"Gmsh over its valid cases: median sj_mean {statistics.median(r['sj_mean'] for r in g_valid):.4f}, "
              f"median irregular {100 * statistics.median(irr(r) for r in g_valid):.1f} %")
    if both:
        print(f"Both valid: {both}; ours better on mean SJ in {better_sj}, on irregular share in "
              f"{better_irr}, on both in {better_both}; at least as good on both (ties within the "
              f"judge's rounding) in {good_both} ({100 * good_both / both:.0f} %); "
              f"quad count ours/Gmsh median {statistics.median(ratios):.3f}, "
              f"range {min(ratios):.3f}..{max(ratios):.3f}")


if __name__ == "__main__":
    main()
