"""Turns the output of .ci/judge_all.sh into the Markdown table of
BENCHMARKS.md: per case the judge's verdict and figures, then medians."""
import json, statistics, sys

rows, done = [], []
for line in open(sys.argv[1]):
    if not (line.startswith("ok") or line.startswith("FAIL")):
        continue
    name = line.split()[1].rstrip(":")
    if "{" in line:
        j = json.loads(line[line.index("{"):])
        if j["valid"]:
            done.append(j)
            rows.append(f"| {name} | valid | {j['quads']} | {j['sj_min']:.3f} | {j['sj_mean']:.3f} | "
                        f"{100 * j['frac_angles_45_135']:.1f} | {j['irregular_interior']} |")
        else:
            rows.append(f"| {name} | INVALID: {'; '.join(j['reasons'])} | | | | | |")
    else:
        msg = line.split(":", 2)[-1].strip() or "time limit"
        rows.append(f"| {name} | not finished: {msg} | | | | | |")
print("| case | judge | quads | SJ min | SJ mean | % quads in [45°,135°] | irregular interior |")
print("|---|---|---:|---:|---:|---:|---:|")
print("\n".join(rows))
if done:
    print(f"\n{len(done)} of {len(rows)} cases meshed and valid. Over those: median of mean SJ "
          f"{statistics.median(j['sj_mean'] for j in done):.3f}, median share in [45°,135°] "
          f"{100 * statistics.median(j['frac_angles_45_135'] for j in done):.1f} %, "
          f"{sum(j['sj_min'] < 0.2 for j in done)} cases with a quad under SJ 0.2.")
