#!/usr/bin/env python3
"""Runs `quadex compare` over the benchmark cases and sums up each model
(thesis Figure 44 over the whole set): cases finished (by extraction, or
with the region fill), median SJ min and mean, median irregular share,
median shares of element steps accepted as predicted, taken with Pn
rescaled to the size field, and replaced by a remedy.

usage: compare_models.py OUTDIR [--models default,rules,thesis,ann]
                         [--jobs 2] [--timeout 60] [--binary PATH] [--cases ...]

Writes OUTDIR/CASE.json per case and OUTDIR/compare.json; prints a
Markdown table.
"""
import json
import os
import statistics
import subprocess
from concurrent.futures import ThreadPoolExecutor

from sweep import default_cases, parse, parser


def run_case(poly, a):
    name = os.path.basename(poly).rsplit(".", 1)[0]
    rep = os.path.join(a.outdir, name + ".json")
    if os.path.exists(rep):
        os.remove(rep)
    try:
        p = subprocess.run([a.binary, "compare", poly, "--models", a.models, "--report", rep],
                           capture_output=True, text=True, timeout=a.timeout)
        if p.returncode != 0:
            return name, None, p.stderr.strip()
    except subprocess.TimeoutExpired:
        return name, None, "timeout"
    return name, json.load(open(rep))["models"], ""


def main():
    ap = parser()
    ap.add_argument("--models", default="default,rules,thesis,ann")
    ap.add_argument("--cases", nargs="*")
    a, _ = parse(ap)
    os.makedirs(a.outdir, exist_ok=True)
    cases = a.cases or default_cases()
    with ThreadPoolExecutor(a.jobs) as ex:
        results = list(ex.map(lambda c: run_case(c, a), cases))
    models = a.models.split(",")
    per = {m: [] for m in models}
    failed = []
    for name, outcomes, err in results:
        if outcomes is None:
            failed.append((name, err))
            continue
        for o in outcomes:
            per[o["model"]].append(o)
    print(f"{len(cases)} cases; {len(failed)} not compared"
          + "".join(f"\n  {n}: {e}" for n, e in failed))
    print("\n| model | finished | of which with the fill | median SJ min | median SJ mean "
          "| median irregular | median accepted as predicted | median rescaled | median replaced |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    summary = {}
    for m in models:
        done = [o for o in per[m] if o["finished"]]
        med = (lambda k: statistics.median(o[k] for o in done)) if done else (lambda k: float("nan"))
        s = {
            "cases": len(per[m]),
            "finished": len(done),
            "fill": sum(o["fill"] for o in done),
            "sj_min": med("sj_min"),
            "sj_mean": med("sj_mean"),
            "irregular_share": med("irregular_share"),
            "accepted_share": med("accepted_share"),
            "rescaled_share": med("rescaled_share"),
            "replaced_share": med("replaced_share"),
        }
        summary[m] = s
        print(f"| {m} | {s['finished']} of {s['cases']} | {s['fill']} | {s['sj_min']:.3f} "
              f"| {s['sj_mean']:.3f} | {100 * s['irregular_share']:.1f} % "
              f"| {100 * s['accepted_share']:.1f} % | {100 * s['rescaled_share']:.1f} % "
              f"| {100 * s['replaced_share']:.1f} % |")
    json.dump({"summary": summary, "failed": failed}, open(os.path.join(a.outdir, "compare.json"), "w"),
              indent=1)


if __name__ == "__main__":
    main()
