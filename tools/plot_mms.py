#!/usr/bin/python3
"""Log-log plot of the 1D manufactured-solution errors against the cell size.

Usage: /usr/bin/python3 tools/plot_mms.py WORK/mms_convergence.csv [WORK/mms_study.csv]
                                          [-o docs/img/mms_convergence.png]

The first file is written by tests/check_mms.py (A = 1e-4, dt = 0.1 h / c); the optional second
one by tests/check_mms.py --study adds the smaller-time-step and large-amplitude series. Errors
are plotted relative to the amplitude A, with slope-2 and slope-1 reference lines.
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def col(rows, key):
    return np.array([float(r[key]) for r in rows])


ap = argparse.ArgumentParser()
ap.add_argument("convergence")
ap.add_argument("study", nargs="?")
ap.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "img", "mms_convergence.png"))
a = ap.parse_args()

conv = read(a.convergence)
h = col(conv, "h")
A0 = 1e-4
fig, ax = plt.subplots(figsize=(6.4, 4.8))
ax.loglog(h, col(conv, "linf") / A0, "o-", color="C0", label="A = 1e-4, dt = 0.1 h/c: L-inf")
ax.loglog(h, col(conv, "rms") / A0, "s--", color="C0", mfc="none",
          label="A = 1e-4, dt = 0.1 h/c: RMS")

if a.study:
    study = read(a.study)

    def series(name, A, update="musl", flip=1.0, cfl=None):
        rows = [r for r in study if r["study"] == name and float(r["A"]) == A and
                r["update"] == update and float(r["flip"]) == flip and
                (cfl is None or float(r["cfl"]) == cfl)]
        return sorted(rows, key=lambda r: float(r["h"]))

    fine = series("fine_dt", 1e-4)
    if fine:
        ax.loglog(col(fine, "h"), col(fine, "linf") / 1e-4, "^-", color="C2",
                  label="A = 1e-4, dt = 0.025 h/c: L-inf")
    for (upd, fl, color) in (("musl", 1.0, "C3"), ("musl", 0.99, "C1"), ("usl", 1.0, "C4")):
        rows = series("large_A", 0.05, upd, fl)
        if rows:
            ax.loglog(col(rows, "h"), col(rows, "linf") / 0.05, "d:", color=color,
                      label="A = 0.05, %s, FLIP %g: L-inf" % (upd.upper(), fl))

# Reference slopes through the coarsest L-inf point, shifted below the data.
e0 = float(conv[0]["linf"]) / A0 / 2
ax.loglog(h, e0 * (h / h[0]) ** 2, "k-", lw=0.8, label="slope 2")
ax.loglog(h, e0 * (h / h[0]), "k:", lw=0.8, label="slope 1")
ax.set_xlabel("cell size h [m]")
ax.set_ylabel("max over one period of |error| / A")
ax.set_title("1D manufactured solution (neo-Hookean, c = 100 m/s, 2x2 particles/cell)",
             fontsize=9)
ax.grid(True, which="both", lw=0.3)
ax.legend(fontsize=7, loc="lower right")
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(a.output)), exist_ok=True)
fig.savefig(a.output, dpi=120)
print("wrote", a.output)
