#!/usr/bin/env python3
"""Stable crack growth in the double cantilever beam (options/dcb_growth.opts): the reaction P
at the arms against the crack length a, with the corrected beam theory's
P(a) = B sqrt(E Gc h^3 / 12) / (a + chi h), chi = 6^(-1/4) (tests/check_dcb_growth.py derives it).
Plots every history row (P against the tip's x: the loading, then the saw-tooth of the growth)
and the rows where the tip grows next (the points the check compares) into
docs/img/dcb_growth.png, and prints the table. One run of the scene, about 4 minutes on one core.

Usage: /usr/bin/python3 runs/dcb_growth.py [--gimp build/gimp] [--work DIR] [--no-run]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import series  # noqa: E402

sys.path.insert(0, os.path.join(series.ROOT, "tests"))
import check_dcb_growth as dcb  # noqa: E402
import gimptest  # noqa: E402


def main():
    a = series.parse_args("dcb_growth")
    out = os.path.join(a.work, "dcb_growth")
    if not a.no_run:
        args = type("A", (), {"gimp": os.path.abspath(a.gimp), "root": series.ROOT,
                              "work": a.work, "mpiexec": "mpiexec", "extra": ""})
        os.makedirs(a.work, exist_ok=True)
        gimptest.run(args, "options/dcb_growth.opts", outdir=out)
    hist = gimptest.history(out)
    pts = dcb.growth_points(hist)
    x = [1e3 * v for v in hist["crack0_tip1_x"]]
    p = [0.5 * (u - d) for u, d in zip(hist["dbc0_fy"], hist["dbc1_fy"])]
    print("| a [mm] | P [N] | P corrected beam theory [N] | P / CBT − 1 |")
    print("| --- | --- | --- | --- |")
    for _, av, _, pv in pts:
        print("| %.0f | %.5f | %.5f | %+.2f %% |" % (1e3 * av, pv, dcb.beam(av),
                                                     100 * (pv / dcb.beam(av) - 1)))
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 1.4]})
    grid_a = [50 + 0.1 * i for i in range(231)]
    ax.plot(grid_a, [dcb.beam(1e-3 * v) for v in grid_a], "k-", lw=1.2,
            label="corrected beam theory, $\\chi = 6^{-1/4}$")
    ax.plot(x, p, "-", color="tab:blue", lw=0.6, alpha=0.6, label="gimp: every history row")
    ax.plot([1e3 * v for _, v, _, _ in pts], [v for _, _, _, v in pts], "o", color="tab:red",
            ms=4, label="gimp: G by J reaches Gc (next increment)")
    ax.set_ylabel("P [N] (reaction per arm)")
    ax.set_ylim(0.2, 0.34)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("DCB, prescribed opening, Gc = 1 J/m$^2$, 2 / 1 mm cells", fontsize=10)
    ax2.axhspan(-100 * dcb.TOL, 100 * dcb.TOL, color="0.9")
    ax2.axhline(0, color="k", lw=0.8)
    ax2.plot([1e3 * v for _, v, _, _ in pts[1:]],
             [100 * (v / dcb.beam(av) - 1) for _, av, _, v in pts[1:]], "o-", color="tab:red",
             ms=4)
    ax2.plot([1e3 * pts[0][1]], [100 * (pts[0][3] / dcb.beam(pts[0][1]) - 1)], "o",
             mfc="none", color="tab:red", ms=4)
    ax2.set_xlabel("crack length a [mm]")
    ax2.set_ylabel("P / CBT − 1 [%]")
    fig.tight_layout()
    png = os.path.join(series.ROOT, "docs", "img", "dcb_growth.png")
    fig.savefig(png, dpi=120)
    print("wrote", png)


if __name__ == "__main__":
    main()
