#!/usr/bin/python3
"""Patch tests on a uniform grid (options/patch.opts) and across three levels (options/patch3.opts):
the measurements of docs/validation.md, section "Patch tests".

Usage: /usr/bin/python3 runs/study_patch.py --gimp build/gimp --root . --work WORK

Runs both scenes as they are, with a particle dump, into WORK/patch and WORK/patch3, writes
WORK/patch.csv and prints the markdown table of the docs. A free block pulled by equal and
opposite tractions p = 1e4 Pa and damped to rest is uniformly stressed: sxx = p,
syy = sxy = 0 and, in plane strain, szz = nu p; the elongation is (1 - nu^2) p / E.
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import gimptest  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--gimp", required=True)
ap.add_argument("--root", required=True)
ap.add_argument("--work", required=True)
args = ap.parse_args()
args.gimp, args.root, args.work = (os.path.abspath(p) for p in (args.gimp, args.root, args.work))
args.mpiexec = "mpiexec"
os.makedirs(args.work, exist_ok=True)

P, NU, E = 1e4, 0.3, 1e7
rows = []
for scene in ("patch", "patch3"):
    out = os.path.join(args.work, scene)
    os.makedirs(out, exist_ok=True)
    dump = os.path.join(out, "particles.csv")
    gimptest.run(args, "options/%s.opts" % scene, ["-gimp_particle_dump", dump], outdir=out)
    d = gimptest.read_csv(dump)
    s = gimptest.summary(out)
    h = gimptest.history(out)
    n = len(d["sxx"])
    W = s["energy"]["external_work"]
    exx = (1 - NU ** 2) * P / E
    span0 = 1.0 - 2 * 0.025  # first to last particle centre along x, initially (level-0 edges)
    span = max(d["x"]) - min(d["x"])
    rows.append({
        "scene": scene, "levels": len(s["levels"]), "particles": n, "steps": s["steps"],
        "wall": s["wall_seconds"],
        "sxx": max(abs(v / P - 1) for v in d["sxx"]),
        "sxx_mean": sum(d["sxx"]) / n / P - 1,
        "syy": max(abs(v) / P for v in d["syy"]),
        "sxy": max(abs(v) / P for v in d["sxy"]),
        "szz": max(abs(v / (NU * P) - 1) for v in d["szz"]),
        "exx": (span / span0 - 1) / exx - 1,
        "W": W, "strain": s["energy"]["strain"], "kinetic": s["energy"]["kinetic"],
        "damping": s["energy"]["damping"],
        "balance_end": h["total"][-1] / W,
        "balance_max": max(abs(x) for x in h["total"]) / W,
    })

with open(os.path.join(args.work, "patch.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)

print("| measure | " + " | ".join("`options/%s.opts` (%d level%s, %d particles)" %
                                   (r["scene"], r["levels"], "s" if r["levels"] > 1 else "",
                                    r["particles"]) for r in rows) + " |")
print("| --- | --- | --- |")
lines = [
    ("max over particles of \\|σxx/p − 1\\|", "sxx", "%.2e"),
    ("mean σxx/p − 1", "sxx_mean", "%+.1e"),
    ("max \\|σyy\\|/p", "syy", "%.2e"),
    ("max \\|σxy\\|/p", "sxy", "%.2e"),
    ("max \\|σzz/(ν p) − 1\\|", "szz", "%.2e"),
    ("elongation / ((1 − ν²) p L / E) − 1", "exx", "%+.1e"),
    ("steps, wall time", None, None),
    ("external work W [J]", "W", "%.4f"),
    ("strain energy at the end [J]", "strain", "%.4f"),
    ("damped energy [J]", "damping", "%.4f"),
    ("kinetic energy at the end [J]", "kinetic", "%.1e"),
    ("balance (kinetic + strain − W + damped) / W at the end", "balance_end", "%+.1e"),
    ("max over the run of \\|balance\\|, / final W", "balance_max", "%.1e"),
]
for label, key, f in lines:
    if key is None:
        print("| %s | %s |" % (label, " | ".join("%d, %.2f s" % (r["steps"], r["wall"]) for r in rows)))
    else:
        print("| %s | %s |" % (label, " | ".join(f % r[key] for r in rows)))
