#!/usr/bin/env python3
"""The plate at rest (options/plate_static.opts): sigma_xx map with every particle drawn as its
rectangle (the paper's Fig. 14, whole quarter and the corner at the hole), and the hoop
stress around the hole against Kirsch (Fig. 15), from an output directory of that scene.

Usage: /usr/bin/python3 tools/plot_plate_maps.py OUTDIR   (e.g. build/output/plate_static)
"""
import csv
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "output", "plate_static")
f = h5py.File(os.path.join(out, "fields.h5"), "r")
last = sorted(f["particles"])[-1]
P = f["particles"][last]
x, l, s = P["x"][:], P["l"][:], P["stress"][:]
p = 10e6

fig, axes = plt.subplots(1, 2, figsize=(12, 5.2))
for ax, lim in zip(axes, (30e-3, 6e-3)):
    rects = [Rectangle((xi - li, yi - lj), 2 * li, 2 * lj)
             for (xi, yi), (li, lj) in zip(x * 1e3, l * 1e3)]
    pc = PatchCollection(rects, cmap="jet", edgecolor="none")
    pc.set_array(s[:, 0] / 1e6)
    pc.set_clim(-10, 32)
    ax.add_collection(pc)
    ax.set_xlim(0, lim * 1e3)
    ax.set_ylim(0, lim * 1e3)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
fig.colorbar(pc, ax=axes, label="sigma_xx [MPa]")
axes[0].set_title("sigma_xx at rest, p = 10 MPa (paper Fig. 14a)")
axes[1].set_title("near the hole (Fig. 14b)")
fig.savefig(os.path.join(ROOT, "docs", "img", "plate_map.png"), dpi=110)

with open(os.path.join(out, "hoop.csv")) as fh:
    rows = list(csv.DictReader(fh))
ang = [float(r["angle_deg"]) for r in rows]
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(ang, [float(r["hoop_over_p"]) for r in rows], "o", ms=3, label="gimp, first particle layer")
ax.plot(ang, [float(r["kirsch"]) for r in rows], "-", label="Kirsch at each particle's radius")
th = [i * math.pi / 180 for i in range(91)]
ax.plot(range(91), [1 - 2 * math.cos(2 * t) for t in th], "--", label="Kirsch at the edge")
ax.set_xlabel("angle from the load axis [deg]")
ax.set_ylabel("sigma_thetatheta / p")
ax.set_title("Hoop stress around the hole (paper Fig. 15)")
ax.grid(alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(ROOT, "docs", "img", "plate_hoop.png"), dpi=120)
