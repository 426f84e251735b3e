#!/usr/bin/env python3
"""Meshes a folder of generated domains (`cargo run --release --example
random_domains -- DIR`) with the release CLI, judges every mesh
(sweep.run_all: the bench's judge.py) and prints a table per family
(the family is the middle part of NNN_family_seed), every failure grouped by
kind, the domains with a quad the boundary does not force past a taper or
aspect ratio of 10 (`unforced`, below), and the worst results by minimum
scaled Jacobian.

usage: domains_sweep.py DOMAINS_DIR OUTDIR [--jobs 2] [--timeout 60]
                        [--binary PATH] [--] [extra `quadex mesh` arguments]

Writes OUTDIR/summary.json with every row.
"""
import json
import os
import statistics
import sys
import time
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sweep import parse, parser, run_all  # noqa: E402

# A quad over this taper or aspect ratio is stretched.
STRETCH = 10.0
# A stretched quad is forced by the boundary when two given segments that
# touch nodes within this many node-rings of it are STRETCH or more apart.
RINGS = 2


def read_poly(path):
    """The nodes (by id) and segments of a .poly file."""
    lines = [line.split("#")[0].split() for line in open(path)]
    lines = [line for line in lines if line]
    n = int(lines[0][0])
    pts = {int(w[0]): (float(w[1]), float(w[2])) for w in lines[1:1 + n]}
    m = int(lines[1 + n][0])
    segs = [(int(w[1]), int(w[2])) for w in lines[2 + n:2 + n + m]]
    return pts, segs


def unforced(poly, msh):
    """The quads of mesh `msh` over STRETCH in taper (adjacent sides) or
    aspect (opposite sides) that the boundary of `poly` does not force:
    no two given segments touching nodes within RINGS node-rings of the quad
    are STRETCH or more apart. A list of (quad, worst ratio)."""
    import meshio
    import numpy as np

    pts, segs = read_poly(poly)
    mesh = meshio.read(msh)
    P = mesh.points[:, :2]
    Q = np.vstack([c.data for c in mesh.cells if c.type == "quad"])
    L = np.linalg.norm(np.roll(P[Q], -1, 1) - P[Q], axis=2)
    taper = np.max(np.maximum(L / np.roll(L, -1, 1), np.roll(L, -1, 1) / L), axis=1)
    aspect = np.maximum(np.maximum(L[:, 0] / L[:, 2], L[:, 2] / L[:, 0]),
                        np.maximum(L[:, 1] / L[:, 3], L[:, 3] / L[:, 1]))
    ratio = np.maximum(taper, aspect)
    stretched = np.nonzero(ratio > STRETCH)[0]
    if len(stretched) == 0:
        return []
    key = {(round(x, 9), round(y, 9)): i for i, (x, y) in enumerate(P)}
    seglen = defaultdict(list)
    for a, b in segs:
        (xa, ya), (xb, yb) = pts[a], pts[b]
        length = ((xa - xb) ** 2 + (ya - yb) ** 2) ** 0.5
        for x, y in (pts[a], pts[b]):
            i = key.get((round(x, 9), round(y, 9)))
            if i is not None:
                seglen[i].append(length)
    node_quads = defaultdict(list)
    for k, q in enumerate(Q):
        for v in q:
            node_quads[v].append(k)
    out = []
    for k in stretched:
        nodes = set(Q[k])
        for _ in range(RINGS):
            nodes |= {v for u in list(nodes) for j in node_quads[u] for v in Q[j]}
        lengths = [x for v in nodes for x in seglen.get(v, [])]
        if len(lengths) < 2 or max(lengths) < STRETCH * min(lengths):
            out.append((int(k), float(ratio[k])))
    return out


def family(case):
    parts = case.split("_")
    return parts[1] if len(parts) >= 3 else "?"


def kind(r):
    """A short name for why a case failed."""
    if r.get("panic"):
        return "panic"
    if r["code"] == -1:
        return "timeout"
    if r["code"] != 0:
        e = r.get("first_error", "")
        for key in ("step limit", "front", "invalid", "refused", "fill"):
            if key in e:
                return f"exit {r['code']}: {key}"
        return f"exit {r['code']}"
    if str(r.get("error", "")).startswith("judge:"):
        return "judge cannot read"
    return "judged invalid"


def main():
    ap = parser("domains")
    a, extra = parse(ap)
    cases = sorted(os.path.join(a.domains, f) for f in os.listdir(a.domains) if f.endswith(".poly"))
    t0 = time.time()
    rows = run_all(cases, a, extra)
    wall = time.time() - t0
    for r, c in zip(rows, cases):
        r["poly"] = os.path.abspath(c)
        r["family"] = family(r["case"])
        r["kind"] = "ok" if r.get("valid") else kind(r)
        if r.get("valid") and (r["taper_max"] > STRETCH or r["aspect_max"] > STRETCH):
            r["unforced"] = unforced(c, os.path.join(a.outdir, r["case"] + ".msh"))
    json.dump(rows, open(os.path.join(a.outdir, "summary.json"), "w"), indent=1)

    fams = defaultdict(list)
    for r in rows:
        fams[r["family"]].append(r)
    print(f"{'family':11} {'tried':>5} {'no fill':>7} {'fill':>4} {'failed':>6} {'t/o':>4} "
          f"{'panic':>5} {'med sjmean':>10} {'worst sjmin':>11} {'taper|asp>10':>12} {'unforced':>8} "
          f"{'fill share':>10}")
    for f in sorted(fams) + ["all"]:
        rs = rows if f == "all" else fams[f]
        ok = [r for r in rs if r.get("valid")]
        fill = sum(r.get("fill", 0) > 0 for r in ok)
        to = sum(r["kind"] == "timeout" for r in rs)
        pan = sum(r["kind"] == "panic" for r in rs)
        failed = len(rs) - len(ok) - to - pan
        med = f"{statistics.median(r['sj_mean'] for r in ok):.4f}" if ok else "-"
        worst = f"{min(r['sj_min'] for r in ok):.4f}" if ok else "-"
        bad = sum(r["taper_max"] > STRETCH or r["aspect_max"] > STRETCH for r in ok)
        loose = sum(bool(r.get("unforced")) for r in ok)
        # The median share of a filled mesh's quads that the fill made.
        # The fill's quads over the quads extraction and the fill left
        # (before finishing changes the mesh).
        shares = [r.get("fill_quads", 0) / max(1, r.get("standing") or r["quads"])
                  for r in ok if r.get("fill", 0) > 0]
        share = f"{100 * statistics.median(shares):.0f} %" if shares else "-"
        print(f"{f:11} {len(rs):5d} {len(ok) - fill:7d} {fill:4d} {failed:6d} {to:4d} {pan:5d} "
              f"{med:>10} {worst:>11} {bad:12d} {loose:8d} {share:>10}")
    groups = defaultdict(list)
    for r in rows:
        if not r.get("valid"):
            groups[r["kind"]].append(r)
    for k in sorted(groups):
        print(f"\n{k}: {len(groups[k])}")
        for r in groups[k]:
            why = r.get("first_error") or "; ".join(r.get("reasons", []))
            if r["kind"] == "judged invalid":
                why = "; ".join(r.get("reasons", []))
            elif r["kind"] == "judge cannot read":
                why = r["error"]
            print(f"  {r['poly']}  {why[:160]}")
    loose = [r for r in rows if r.get("unforced")]
    print(f"\nwith a quad over {STRETCH:g} the boundary does not force "
          f"(no given segments {STRETCH:g}× apart within {RINGS} node-rings): {len(loose)}")
    for r in loose:
        worst = max(x for _, x in r["unforced"])
        print(f"  {r['poly']}  {len(r['unforced'])} quads, worst {worst:.2f}, fill {r.get('fill', 0)}")
    ok = sorted((r for r in rows if r.get("valid")), key=lambda r: r["sj_min"])
    print("\nworst by sj_min:")
    for r in ok[:5]:
        print(f"  {r['poly']}  sj_min {r['sj_min']:.4f} sj_mean {r['sj_mean']:.4f} "
              f"taper {r['taper_max']:.2f} aspect {r['aspect_max']:.2f} fill {r.get('fill', 0)}")
    print(f"\n{len(rows)} cases in {wall:.0f} s wall, {a.jobs} jobs")


if __name__ == "__main__":
    main()
