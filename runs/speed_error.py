#!/usr/bin/env python3
"""Speed against error on the plate with a hole at rest (paper section 4.4): uniform grids and
two- and three-level refined grids, each run to rest by options/plate*_static.opts. The error is
the edge's, as docs/method.md "Hole measure" fits it from the particles around the whole edge:
kt (the fitted edge curve at 90 degrees) against Kirsch's 3 times the finite-width factor of a
strip (d/W = 1/15: 1.0047), and the curve's largest distance from Kirsch's 1 - 2 cos 2 theta
(summary.json hoop_max_error, in p; the finite width alone moves the curve by up to 0.014 p).
Writes a Markdown table to stdout and docs/img/speed_error.png.

Usage: /usr/bin/python3 runs/speed_error.py [--gimp build/gimp] [--work DIR] [--no-run]
"""
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
KT_REF = 3 * 1.0047


def main():
    a = series.parse_args("speed_error")
    rows = []
    # The static scenes include plate*.opts, which lie next to them in options/.
    for name, kind, _, s in series.run_series(a, RUNS, cwd=os.path.join(ROOT, "options")):
        m = s["measures"]
        rows.append((name, kind, s["particles"], s["wall_seconds"], m["kt"],
                     abs(m["kt"] / KT_REF - 1), m["hoop_max_error"]))
    print("| grid | particles | wall [s] | kt | kt error | edge curve max error [p] |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, kind, n, w, kt, err, curve in rows:
        print("| %s | %d | %.1f | %.4f | %.2f %% | %.4f |" % (name, n, w, kt, 100 * err, curve))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, col, label in ((axs[0], 5, "|kt / 3.014 - 1|"),
                           (axs[1], 6, "edge curve: max |hoop - Kirsch| / p")):
        for kind, mark in (("uniform", "o-"), ("refined", "s")):
            pts = [(r[3], r[col], r[0]) for r in rows if r[1] == kind]
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], mark, label=kind)
            for w, err, name in pts:
                ax.annotate(name, (w, err), fontsize=7, xytext=(4, 4), textcoords="offset points")
        ax.set_xlabel("wall time [s] (1 rank)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("Plate with a hole at rest: edge error against wall time")
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "img", "speed_error.png"), dpi=120)


if __name__ == "__main__":
    main()
