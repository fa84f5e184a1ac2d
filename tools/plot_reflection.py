#!/usr/bin/python3
"""Log-log plot of the reflected energy fraction at the level interfaces against k h0.

Usage: /usr/bin/python3 tools/plot_reflection.py WORK/reflection.csv
                                                 [-o docs/img/reflection.png]

The file is written by tests/check_reflection.py. Plotted: the energy of the reflected wave
(the particle-by-particle difference from the reference grid) at the coarse-to-fine and the
fine-to-coarse interface, the energy the reference runs hold on the same incoming sides (the
dispersion tail of the incident pulse, which the difference removes), and lines of slope 2
and 4 through the finest coarse-to-fine point.
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

ap = argparse.ArgumentParser()
ap.add_argument("csv")
ap.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "img", "reflection.png"))
a = ap.parse_args()

with open(a.csv) as f:
    rows = sorted(csv.DictReader(f), key=lambda r: float(r["kh0"]))


def col(key):
    return np.array([float(r[key]) for r in rows])


kh = col("kh0")
fig, ax = plt.subplots(figsize=(6.4, 4.8))
ax.loglog(kh, col("c2f"), "o-", color="C0", label="coarse → fine: reflected")
ax.loglog(kh, col("f2c"), "s-", color="C1", label="fine → coarse: reflected")
ax.loglog(kh, col("c2f_background"), "o:", color="C0", mfc="none",
          label="coarse side, uniform grid (dispersion tail)")
ax.loglog(kh, col("f2c_background"), "s:", color="C1", mfc="none",
          label="fine side, no fine → coarse interface (tail)")
x = np.array([kh.min(), kh.max()])
y0 = col("c2f")[0]
ax.loglog(x, y0 * (x / kh[0]) ** 2, "k--", lw=1, label="slope 2")
ax.loglog(x, y0 * (x / kh[0]) ** 4, "k-.", lw=1, label="slope 4")
ax.set_xlabel("k h0  (k = 2π / pulse width, h0 = coarse cell)")
ax.set_ylabel("energy fraction of the pulse")
ratio = rows[0].get("ratio", "2")
ax.set_title("Wave reflection at level interfaces (ratio %s)" % ratio)
ax.grid(True, which="both", ls=":", lw=0.5)
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(a.output)), exist_ok=True)
fig.savefig(a.output, dpi=120)
print("wrote %s" % a.output)
