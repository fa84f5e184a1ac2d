#!/usr/bin/python3
"""Plate with a hole (paper section 4.4): sigma_xx / p of the particle at the top of the hole
against time, for the paper's dynamic run (d = 1000 1/s, 4000 steps) and for the damped runs
to rest (d = 3e5 1/s) with FLIP 1 and PIC.

Usage: /usr/bin/python3 tools/plot_plate.py WORK [-o docs/img/plate.png]

WORK is the directory runs/study_plate.py wrote.
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
ap.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "img", "plate.png"))
a = ap.parse_args()
P = 10e6


def load(name):
    with open(os.path.join(a.work, name, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return (np.array([1e6 * float(r["time"]) for r in rows]),
            np.array([float(r["hole_top_sxx"]) / P for r in rows]))


with open(os.path.join(a.work, "plate.csv")) as f:
    table = {r["name"]: r for r in csv.DictReader(f)}

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
for name, style, label in (("paper_3level", "C0-", "3 levels 1.0 / 0.5 / 0.25 mm"),
                           ("paper_h0.25", "C1--", "uniform 0.25 mm")):
    t, k = load(name)
    ax1.plot(t, k, style, lw=1.2, label=label)
ax1.axvline(40, color="0.5", lw=0.8)
ax1.set_title("(a) the paper's run: d = 1000 1/s, dt = 10 ns, 4000 steps (scene FLIP 0.99)", fontsize=9)
for name, style, label in (("static_flip1_3level", "C0-", "3 levels, FLIP 1"),
                           ("static_flip1_h0.25", "C1-", "uniform 0.25 mm, FLIP 1"),
                           ("static_pic_3level", "C2-", "3 levels, PIC (FLIP 0)"),
                           ("static_pic_h0.25", "C3--", "uniform 0.25 mm, PIC")):
    t, k = load(name)
    ax2.plot(t, k, style, lw=1.2, label=label)
kir = float(table["static_pic_3level"]["kirsch_r"])
ax2.axhline(kir, color="k", ls=":", lw=1, label="Kirsch at the particle (r = %.3f mm): %.3f" %
            (float(table["static_pic_3level"]["r_mm"]), kir))
ax2.axhline(3.014, color="k", ls="--", lw=1, label="finite width, at the edge: 3.014")
ax2.set_ylim(2.6, 3.55)
ax2.set_title("(b) damped to rest: d = 3e5 1/s, 20000 steps", fontsize=9)
for ax in (ax1, ax2):
    ax.set_xlabel("time [µs]")
    ax.set_ylabel("σxx / p at the top of the hole")
    ax.grid(True, lw=0.3)
ax1.legend(fontsize=8, loc="lower right")
ax2.legend(fontsize=8, loc="upper right", ncol=2)
fig.suptitle("Plate with a hole, quarter model: 60 x 60 mm, hole 4 mm, p = 10 MPa, copper, "
             "plane stress", fontsize=9)
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(a.output)), exist_ok=True)
fig.savefig(a.output, dpi=110)
print("wrote", a.output)
