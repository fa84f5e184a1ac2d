#!/usr/bin/python3
"""Hole edge convergence: the hoop stress around the edge of a circular hole against Kirsch's
curve, on a plate wide enough to be infinite (options/plate_wide.opts: width / hole diameter 40,
gross-section finite-width factor 1.0003) and on the paper's plate (options/plate_static.opts,
d/W = 1/15, whose finite-width gross-section kt is (2 + (1 - d/W)^3) / (1 - d/W) = 3.014).
The measurements of docs/validation.md, section "Hole edge convergence".

Usage: /usr/bin/python3 runs/study_hole.py --gimp build/gimp --root . --work WORK [--no-run]
       [--finest 7]

Runs, into WORK/<name>:
  wide_L4 ... wide_L7         plate_wide.opts with 4 to 7 levels: finest cell a / 4, a / 8,
                              a / 16, a / 32 next to the hole, cut cells (the default)
  wide_L4_nocut, wide_L5_nocut  the same without cut cells (-gimp_cut_cells false)
  paper_L3, paper_L4, paper_L5  plate_static.opts, 0.25 mm next to the hole, and one and two more
                              levels (0.125, 0.0625 mm) around the hole
Each reports kt (the fitted edge hoop stress at 90 degrees, summary.json "kt"), the largest
distance of the fitted edge curve from Kirsch's (hoop_max_error, 5-degree bins, the wide plate
only: the paper's plate is not infinite), the particles and the wall time. Writes WORK/hole.csv,
docs/img/hole_edge.png (the edge curves against Kirsch's) and prints the markdown table.
"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import gimptest  # noqa: E402
from check_hole import levels as wide_levels  # noqa: E402

FW_PAPER = (2 + (1 - 1 / 15) ** 3) / (1 - 1 / 15)
FW_WIDE = (2 + (1 - 1 / 40) ** 3) / (1 - 1 / 40) / 3.0 * 3.0


def paper_levels(n):
    boxes = {3: "-0.5e-3,-0.5e-3,3e-3,3e-3", 4: "-0.25e-3,-0.25e-3,2.5e-3,2.5e-3"}
    extra = ["-gimp_levels", str(n)]
    for k in range(3, n):
        extra += ["-gimp_level%d_box" % k, boxes[k], "-gimp_level%d_ratio" % k, "2"]
    return extra


def runs(finest):
    out = []
    for n in range(4, finest + 1):
        out.append(("wide_L%d" % n, "options/plate_wide.opts", wide_levels(n), 2.0 ** (n - 2)))
    for n in (4, 5):
        out.append(("wide_L%d_nocut" % n, "options/plate_wide.opts",
                    wide_levels(n) + ["-gimp_cut_cells", "false"], 2.0 ** (n - 2)))
    for n in range(3, min(finest, 6)):
        out.append(("paper_L%d" % n, "options/plate_static.opts",
                    paper_levels(n) + ["-gimp_static_tol", "1e-7"], 2.0 ** (n - 1) * 2))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--no-run", action="store_true")
    ap.add_argument("--finest", type=int, default=7, help="levels of the finest wide run")
    args = ap.parse_args()
    args.gimp, args.root, args.work = (os.path.abspath(p) for p in (args.gimp, args.root,
                                                                     args.work))
    args.extra = ""
    os.makedirs(args.work, exist_ok=True)
    rows = []
    for name, opts, extra, cells in runs(args.finest):
        outdir = os.path.join(args.work, name)
        if not args.no_run:
            gimptest.run(args, opts, extra=extra, outdir=outdir)
        s = gimptest.summary(outdir)
        m = s["measures"]
        ref = FW_PAPER if name.startswith("paper") else 3.0
        rows.append({"run": name, "cells_per_radius": cells, "particles": s["particles"],
                     "steps": s["steps"], "wall_s": s["wall_seconds"], "kt": m["kt"],
                     "kt_ref": ref, "kt_err_pct": 100 * (m["kt"] / ref - 1),
                     "kt_particle": m["kt_particle"], "hoop_max_error": m["hoop_max_error"]})
    with open(os.path.join(args.work, "hole.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("| run | cells per radius | particles | steps | wall [s] | kt | kt error | "
          "first particle at 90 deg | max edge error [p] |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print("| %s | %g | %d | %d | %.0f | %.4f | %+.2f %% | %.4f | %s |" % (
            r["run"], r["cells_per_radius"], r["particles"], r["steps"], r["wall_s"], r["kt"],
            r["kt_err_pct"], r["kt_particle"],
            "%.3f" % r["hoop_max_error"] if r["run"].startswith("wide") else "-"))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    th = [i * 0.5 for i in range(181)]
    ax.plot(th, [1 - 2 * math.cos(2 * math.radians(t)) for t in th], "k-", label="Kirsch")
    for r in rows:
        if not r["run"].startswith("wide"):
            continue
        c = gimptest.read_csv(os.path.join(args.work, r["run"], "hoop_fit.csv"))
        ax.plot(c["angle_deg"], c["edge_hoop_over_p"],
                "o-" if "nocut" not in r["run"] else "x--", ms=3,
                label="%s (a / %g)" % (r["run"], r["cells_per_radius"]))
    ax.set_xlabel("angle from the load axis [deg]")
    ax.set_ylabel("edge hoop stress / p")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(args.root, "docs", "img", "hole_edge.png"), dpi=110)


if __name__ == "__main__":
    main()
