#!/usr/bin/env python3
"""Speed against error on the plate with a hole at rest (paper section 4.4): uniform grids and
two- and three-level refined grids, each run to rest by options/plate*_static.opts. The error of
kt (hoop stress / p of the particle next to the top of the hole) is taken against Kirsch's
solution at that particle's radius times the finite-width factor of a strip (Heywood,
d/W = 1/15: 1.0047). Writes a Markdown table to stdout and docs/img/speed_error.png.

Usage: /usr/bin/python3 runs/speed_error.py [--gimp build/gimp] [--work DIR] [--no-run]
"""
import math
import os

import series

ROOT = series.ROOT
RUNS = [  # name, scene, extra options, kind
    ("uniform 1.0 mm", "plate_uniform_static.opts", ["-gimp_h", "1e-3"], "uniform"),
    ("uniform 0.5 mm", "plate_uniform_static.opts", ["-gimp_h", "0.5e-3"], "uniform"),
    ("uniform 0.25 mm", "plate_uniform_static.opts", ["-gimp_h", "0.25e-3"], "uniform"),
    ("uniform 0.125 mm", "plate_uniform_static.opts", ["-gimp_h", "0.125e-3"], "uniform"),
    ("2 levels 0.5/0.25 mm", "plate_uniform_static.opts",
     ["-gimp_h", "0.5e-3", "-gimp_levels", "2", "-gimp_level1_box", "-0.5e-3,-0.5e-3,5e-3,5e-3",
      "-gimp_level1_ratio", "2"], "refined"),
    ("3 levels 1.0/0.5/0.25 mm", "plate_static.opts", [], "refined"),
    ("3 levels 0.5/0.25/0.125 mm", "plate_static.opts", ["-gimp_h", "0.5e-3"], "refined"),
]
HOLE, WIDTH_FACTOR = 2e-3, 1.0047


def kirsch_90(r):
    a2 = (HOLE / r) ** 2
    return 0.5 * (1 + a2) + 0.5 * (1 + 3 * a2 * a2)


def main():
    a = series.parse_args("speed_error")
    rows = []
    # The static scenes include plate*.opts, which lie next to them in options/.
    for name, kind, _, s in series.run_series(a, RUNS, cwd=os.path.join(ROOT, "options")):
        pr = s["probes"]["hole_top"]
        r = math.hypot(pr["x0"][0] + pr["u"][0], pr["x0"][1] + pr["u"][1])
        ref = kirsch_90(r) * WIDTH_FACTOR
        kt = s["measures"]["kt"]
        rows.append((name, kind, s["particles"], s["wall_seconds"], kt, r, ref, abs(kt / ref - 1)))
    print("| grid | particles | wall [s] | kt | particle r [mm] | reference | error |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, kind, n, w, kt, r, ref, err in rows:
        print("| %s | %d | %.1f | %.4f | %.4f | %.4f | %.2f %% |" % (name, n, w, kt, r * 1e3, ref,
                                                                  100 * err))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for kind, mark in (("uniform", "o-"), ("refined", "s")):
        pts = [(w, err, name) for name, k, n, w, kt, r, ref, err in rows if k == kind]
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], mark, label=kind)
        for w, err, name in pts:
            ax.annotate(name, (w, err), fontsize=7, xytext=(4, 4), textcoords="offset points")
    ax.set_xlabel("wall time [s] (1 rank)")
    ax.set_ylabel("|kt / reference - 1|")
    ax.set_title("Plate with a hole at rest: error against wall time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "img", "speed_error.png"), dpi=120)


if __name__ == "__main__":
    main()
