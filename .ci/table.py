"""The Markdown table of BENCHMARKS.md from a sweep.py summary (and, given,
gmsh_compare.py's gmsh_summary.json): per case quads, scaled Jacobian
min/mean, irregular interior share, taper and aspect maxima, steps by kind,
and Gmsh's figures beside ours.

usage: table.py SUMMARY.json [GMSH_SUMMARY.json]"""
import json
import statistics
import sys

ours = json.load(open(sys.argv[1]))
gmsh = {}
if len(sys.argv) > 2:
    gmsh = {r["case"]: r for r in json.load(open(sys.argv[2]))}


def irr(r):
    return 100 * r["irregular_interior"] / max(r["interior_nodes"], 1)


short = {"Element": "E", "Square": "Sq", "Close4": "C4", "Close6": "C6", "Relax": "Rx",
         "Seam": "Se", "Transition": "Tr", "Mapped": "Map", "Split": "Sp", "Bridge": "Br", "RipUp": "Rip", "Fill": "FILL"}
print("| case | quads | SJ min | SJ mean | irregular % | taper max | aspect max | steps by kind "
      "| Gmsh quads | Gmsh SJ mean | Gmsh irregular % |")
print("|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|")
for r in ours:
    g = gmsh.get(r["case"])
    gs = (f"{g['quads']} | {g['sj_mean']:.3f} | {irr(g):.1f}" if g and g.get("valid")
          else ("invalid (triangles left) | | " if g else " | | "))
    if not r.get("valid"):
        print(f"| {r['case']} | not finished: {r.get('error', '')[:60]} | | | | | | | {gs} |")
        continue
    kinds = " ".join(f"{short.get(k, k)} {v}" for k, v in r.get("kinds", {}).items())
    print(f"| {r['case']} | {r['quads']} | {r['sj_min']:.3f} | {r['sj_mean']:.3f} | {irr(r):.1f} | "
          f"{r['taper_max']:.2f} | {r['aspect_max']:.2f} | {kinds} | {gs} |")
ok = [r for r in ours if r.get("valid")]
print()
print(f"Valid: {len(ok)} of {len(ours)}; with a Fill step: {sum(1 for r in ok if r.get('fill'))}; "
      f"median SJ mean {statistics.median(r['sj_mean'] for r in ok):.3f}; "
      f"median irregular {statistics.median(irr(r) for r in ok):.1f} %; "
      f"worst taper {max(r['taper_max'] for r in ok):.2f}; "
      f"worst aspect {max(r['aspect_max'] for r in ok):.2f}.")
