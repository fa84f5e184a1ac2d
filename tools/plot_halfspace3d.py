#!/usr/bin/python3
"""The half-space under a circular load in 3D: sigma_z on the axis against depth, and sigma_z in
the symmetry plane y = 0 near the load.

Usage: /usr/bin/python3 tools/plot_halfspace3d.py WORK [-o docs/img/halfspace3d.png]

WORK is the work directory of tests/check_halfspace3d.py: halfspace3d_axis.csv (the axis curve
fitted from the particles) and halfspace3d_particles.csv (the final particle dump).
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
ap.add_argument("work")
ap.add_argument("-o", default=os.path.join(ROOT, "docs", "img", "halfspace3d.png"))
a = ap.parse_args()
p, rad = 1000.0, 1.0

with open(os.path.join(a.work, "halfspace3d_axis.csv")) as f:
    axis = list(csv.DictReader(f))
with open(os.path.join(a.work, "halfspace3d_particles.csv")) as f:
    parts = list(csv.DictReader(f))
z = np.array([float(r["z_over_a"]) for r in axis])
s = np.array([float(r["sigma_z"]) for r in axis])
zz = np.linspace(0.0, 3.0, 200)
exact = -p * (1 - zz ** 3 / (rad ** 2 + zz ** 2) ** 1.5)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
ax1.plot(-exact / p, zz, "k-", label="exact (Boussinesq, circular load)")
ax1.plot(-s / p, z, "o", color="C3", label="gimp, 3 levels (axis value fitted from particles)")
ax1.invert_yaxis()
ax1.set_xlabel(r"$-\sigma_z / p$ on the axis")
ax1.set_ylabel("depth z / a")
ax1.axhline(3.0, color="0.7", lw=0.8)
ax1.text(0.02, 2.95, "finest level ends", color="0.5", fontsize=8, va="bottom")
ax1.legend(fontsize=8, loc="lower right")
ax1.grid(alpha=0.3)

x = np.array([float(r["x"]) for r in parts])
y = np.array([float(r["y"]) for r in parts])
zp = np.array([float(r["z"]) for r in parts])
sz = np.array([float(r["szz"]) for r in parts])
near = (y < 0.13) & (x < 3.0) & (zp > -3.0)  # the first layer of particles next to y = 0
sc = ax2.scatter(x[near], -zp[near], c=sz[near] / p, s=14, cmap="viridis_r", vmin=-1, vmax=0)
ax2.invert_yaxis()
ax2.set_aspect("equal")
ax2.set_xlabel("x / a")
ax2.set_ylabel("depth z / a")
ax2.set_title(r"$\sigma_z / p$, particles next to the plane y = 0", fontsize=9)
ax2.plot([0, rad], [0, 0], "r-", lw=3)
fig.colorbar(sc, ax=ax2, shrink=0.8)
fig.tight_layout()
fig.savefig(a.o, dpi=110)
print("wrote", a.o)
