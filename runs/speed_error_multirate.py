#!/usr/bin/env python3
"""Speed against error with a time step per level (-gimp_multirate): the 1D manufactured solution
(options/mms_skb1d.opts, A = 1e-4, FLIP, MUSL, one period) on three grids at each h0 = 1/n:

  uniform        one level of h0, dt = 0.1 h0 / c;
  2 levels       level 1 (ratio 2) on x in [0.4375, 0.5625], every level with the fine dt;
  2 levels, mr   the same grid with -gimp_multirate true (level 0 steps with 2 dt).

The level-1 box holds 36 % of the particles (4 times their density on an eighth of the bar). The
error is the largest displacement error over the period and all particles, sampled every 2 fine
steps on every grid (summary.json mms_linf); the cost is the run's wall time (one rank; each run
three times, the fastest kept).
Writes a Markdown table to stdout and docs/img/speed_error_multirate.png.

Usage: /usr/bin/python3 runs/speed_error_multirate.py [--gimp build/gimp] [--work DIR] [--no-run]
"""
import os

import series

ROOT = series.ROOT
NS = (64, 128, 256, 512)
REPEAT = 3


def grids(n):
    h = 1.0 / n
    base = ["-gimp_h", repr(h), "-gimp_body0_box", "0,0,1,%r" % h, "-gimp_bc3_y", repr(h),
            "-gimp_transfer", "flip"]
    two = ["-gimp_levels", "2", "-gimp_level1_ratio", "2", "-gimp_level1_box",
           "0.4375,0,0.5625,%r" % h]
    return [("uniform 1/%d" % n, "options/mms_skb1d.opts", base, "uniform"),
            ("2 levels 1/%d" % n, "options/mms_skb1d.opts", base + two, "2 levels"),
            ("2 levels 1/%d, mr" % n, "options/mms_skb1d.opts",
             base + two + ["-gimp_multirate", "true"], "2 levels, multi-rate")]


def main():
    a = series.parse_args("speed_error_multirate")
    runs = [r for n in NS for r in grids(n)] * REPEAT
    best = {}
    for name, kind, _, s in series.run_series(a, runs, ["-gimp_history_interval", "2"],
                                              cwd=ROOT):
        m = s["measures"]
        w = s["wall_seconds"]
        if name not in best or w < best[name][2]:
            best[name] = (kind, s["particles"], w, m["mms_linf"])
    rows = [(name,) + best[name] for name, _, _, _ in runs[:len(NS) * 3]]
    print("| grid | particles | wall [s] | L-inf error [m] |")
    print("| --- | --- | --- | --- |")
    for name, kind, n, w, err in rows:
        print("| %s | %d | %.3f | %.3e |" % (name, n, w, err))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for kind, mark in (("uniform", "o-"), ("2 levels", "s-"), ("2 levels, multi-rate", "^-")):
        pts = [(r[3], r[4]) for r in rows if r[1] == kind]
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], mark, label=kind)
    ax.set_xlabel("wall time [s] (1 rank)")
    ax.set_ylabel("max displacement error [m]")
    ax.set_title("1D manufactured solution, h0 = 1/64 ... 1/512")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    path = os.path.join(ROOT, "docs", "img", "speed_error_multirate.png")
    fig.savefig(path, dpi=120)
    print("wrote %s" % path)


if __name__ == "__main__":
    main()
