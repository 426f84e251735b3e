#!/usr/bin/env python3
"""Meshes benchmark boundaries with the release CLI, judges every mesh with
the bench's judge.py, and prints one row per case and the medians.

usage: sweep.py OUTDIR [--jobs 2] [--timeout 60] [--cases DIR_OR_FILE ...]
                [--] [extra `quadex mesh` arguments]

Without --cases: ../shared/bench/boundaries (less disk1600, disk6400), peer
and edge. Writes OUTDIR/summary.json with every row.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BENCH = os.path.join(ROOT, "..", "shared", "bench")
JUDGE = os.path.join(BENCH, "tools", "judge.py")
sys.path.insert(0, os.path.join(BENCH, "tools"))
from judge import evaluate  # noqa: E402


def default_cases():
    out = []
    for d in ("boundaries", "peer", "edge"):
        for f in sorted(os.listdir(os.path.join(BENCH, d))):
            if f.endswith(".poly") and f not in ("disk1600.poly", "disk6400.poly"):
                out.append(os.path.join(BENCH, d, f))
    return out


def run_case(poly, outdir, binary, extra, timeout):
    name = os.path.basename(poly).rsplit(".", 1)[0]
    msh = os.path.join(outdir, name + ".msh")
    rep = os.path.join(outdir, name + ".json")
    for p in (msh, rep):
        if os.path.exists(p):
            os.remove(p)
    t0 = time.time()
    try:
        p = subprocess.run([binary, "mesh", poly, "-o", msh, "--report", rep] + extra,
                           capture_output=True, text=True, timeout=timeout)
        lines = p.stderr.strip().splitlines() or [""]
        code, err, first = p.returncode, lines[-1], lines[0]
        panic = "panicked" in p.stderr
    except subprocess.TimeoutExpired:
        code, err, first, panic = -1, "timeout", "timeout", False
    secs = time.time() - t0
    row = {"case": name, "code": code, "seconds": round(secs, 3), "error": err,
           "first_error": first, "panic": panic}
    if code != 0 or not os.path.exists(msh):
        return row
    try:
        j = evaluate(poly, msh)
    except Exception as e:  # a mesh the judge cannot read
        row["error"] = f"judge: {e}"
        row["valid"] = False
        return row
    row.update(j)
    if os.path.exists(rep):
        r = json.load(open(rep))
        kinds = r.get("steps", {}).get("by_kind", {})
        row["kinds"] = kinds
        row["fill"] = kinds.get("Fill", 0)
        row["fill_quads"] = r.get("steps", {}).get("quads_by_kind", {}).get("Fill", 0)
        row["standing"] = r.get("steps", {}).get("standing", 0)
    return row


def parser(*positional):
    """The options every sweep takes (`positional` first, then OUTDIR,
    --jobs, --timeout, --binary)."""
    ap = argparse.ArgumentParser()
    for name in positional:
        ap.add_argument(name)
    ap.add_argument("outdir")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=60)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "quadex"))
    return ap


def parse(ap):
    """Parses the command line; what follows `--` goes to `quadex mesh`."""
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        k = argv.index("--")
        argv, extra = argv[:k], argv[k + 1:]
    return ap.parse_args(argv), extra


def run_all(cases, a, extra):
    """Meshes and judges `cases`, `a.jobs` at a time, in order."""
    os.makedirs(a.outdir, exist_ok=True)
    with ThreadPoolExecutor(a.jobs) as ex:
        return list(ex.map(lambda c: run_case(c, a.outdir, a.binary, extra, a.timeout), cases))


def main():
    ap = parser()
    ap.add_argument("--cases", nargs="*")
    a, extra = parse(ap)
    cases = []
    for c in a.cases or []:
        if os.path.isdir(c):
            cases += sorted(os.path.join(c, f) for f in os.listdir(c) if f.endswith(".poly"))
        else:
            cases.append(c)
    cases = cases or default_cases()
    rows = run_all(cases, a, extra)
    print(f"{'case':28} {'ok':>5} {'quads':>7} {'sjmin':>6} {'sjmean':>6} {'irr%':>5} "
          f"{'taper':>7} {'aspect':>7} {'fill':>4} {'secs':>6}")
    good = []
    for r in rows:
        if r.get("valid"):
            good.append(r)
            irr = 100 * r["irregular_interior"] / max(r["interior_nodes"], 1)
            print(f"{r['case']:28} {'ok':>5} {r['quads']:7d} {r['sj_min']:6.3f} {r['sj_mean']:6.3f} "
                  f"{irr:5.1f} {r['taper_max']:7.2f} {r['aspect_max']:7.2f} {r.get('fill', 0):4d} "
                  f"{r['seconds']:6.2f}")
        else:
            why = r.get("error") or "; ".join(r.get("reasons", []))
            print(f"{r['case']:28} {'FAIL':>5} {why[:90]}")
    if good:
        irr = [r["irregular_interior"] / max(r["interior_nodes"], 1) for r in good]
        print(f"\n{len(good)} of {len(rows)} valid; with a Fill step: {sum(r.get('fill', 0) > 0 for r in good)}; "
              f"median sj_mean {statistics.median(r['sj_mean'] for r in good):.4f}; "
              f"median irregular {100 * statistics.median(irr):.1f} %; "
              f"worst taper {max(r['taper_max'] for r in good):.2f}; "
              f"worst aspect {max(r['aspect_max'] for r in good):.2f}; "
              f"taper or aspect > 10: {sum(r['taper_max'] > 10 or r['aspect_max'] > 10 for r in good)}; "
              f"sj_min < 0.3: {sum(r['sj_min'] < 0.3 for r in good)}; "
              f"median secs {statistics.median(r['seconds'] for r in rows):.2f}")
    json.dump(rows, open(os.path.join(a.outdir, "summary.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
