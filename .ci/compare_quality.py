"""Compares quadex's quality report (--report JSON) with judge.py's figures
for every judged case in OUTDIR: they must agree to the judge's rounding."""
import glob, json, os, sys

out = sys.argv[1]
fields = {"sj_min": 4, "sj_mean": 4, "frac_angles_45_135": 4, "min_angle": 3, "max_angle": 3,
          "aspect_max": 3, "taper_max": 3, "irregular_interior": 0, "quads": 0}
bad = n = 0
judged = {}
for line in open(os.path.join(out, "judge.txt")):
    parts = line.split(" ", 2)
    if line.startswith("ok"):
        name = line.split()[1]
        judged[name] = json.loads(line[line.index("{"):])
for name, j in sorted(judged.items()):
    q = json.load(open(os.path.join(out, name + ".json")))["quality"]
    n += 1
    for f, d in fields.items():
        mine = round(q[f], d) if d else q[f]
        if abs(mine - j[f]) > 1.01 * 10 ** -d if d else mine != j[f]:
            print(f"{name}: {f} quadex {q[f]} judge {j[f]}")
            bad += 1
print(f"quality agrees with judge.py on {n - (bad > 0)} of {n} cases" if not bad else f"{bad} disagreements")
sys.exit(1 if bad else 0)
