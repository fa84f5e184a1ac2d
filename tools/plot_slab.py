#!/usr/bin/python3
"""Displacement-controlled slab (paper section 4.3, options/slab.opts): displacement and stress at
the probe particle against time, damped and undamped, as the paper's Fig. 12 (a) and (b).

Usage: /usr/bin/python3 tools/plot_slab.py WORK [-o docs/img/slab.png]

WORK is the directory runs/study_slab.py wrote (WORK/damped and WORK/undamped). The exact
static values: u_x = delta x0 / L at the probe's initial x0; sigma_xx = E' delta / L in small
strain and E' ln(1 + delta / L) for the rate-form (logarithmic-strain) model of the code.
"""
import argparse
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ap = argparse.ArgumentParser()
ap.add_argument("work")
ap.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "img", "slab.png"))
a = ap.parse_args()

E, NU, L, DELTA = 175.8e9, 0.28, 10e-3, 0.5e-3
EP = E / (1 - NU ** 2)


def load(name):
    d = os.path.join(a.work, name)
    with open(os.path.join(d, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(d, "summary.json")) as f:
        s = json.load(f)
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}, s


dmp, s = load("damped")
und, _ = load("undamped")
x0 = s["probes"]["probe"]["x0"][0]
u_exact = DELTA * x0 / L

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
for h, style, label in ((und, "C1-", "no damping"), (dmp, "C0-", "damping d = 1e6 1/s")):
    t = 1e6 * h["time"]
    ax1.plot(t, 1e3 * h["probe_ux"], style, lw=1.2, label=label)
    ax2.plot(t, 1e-9 * h["probe_sxx"], style, lw=1.2, label=label)
ax1.axhline(1e3 * u_exact, color="k", ls="--", lw=1,
            label="static: δ x0 / L = %.5f mm" % (1e3 * u_exact))
ax2.axhline(1e-9 * EP * DELTA / L, color="k", ls="--", lw=1,
            label="E' δ / L = %.3f GPa (small strain)" % (1e-9 * EP * DELTA / L))
ax2.axhline(1e-9 * EP * math.log(1 + DELTA / L), color="k", ls=":", lw=1,
            label="E' ln(1 + δ/L) = %.3f GPa" % (1e-9 * EP * math.log(1 + DELTA / L)))
ax1.set_title("(a) displacement u_x of the particle at (%.3f, %.3f) mm" %
              tuple(1e3 * v for v in s["probes"]["probe"]["x0"]), fontsize=9)
ax2.set_title("(b) normal stress σxx of the same particle", fontsize=9)
ax1.set_ylabel("u_x [mm]")
ax2.set_ylabel("σxx [GPa]")
for ax in (ax1, ax2):
    ax.set_xlabel("time [µs]")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.axvline(10, color="0.6", lw=0.8)
fig.suptitle("Slab 10 x 3 mm, silicon, plane strain: right end displaced by δ = 0.5 mm over "
             "10 µs (penalty, Eq. 9), left end on rollers", fontsize=9)
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(a.output)), exist_ok=True)
fig.savefig(a.output, dpi=110)
print("wrote", a.output)
for name, h in (("damped", dmp), ("undamped", und)):
    t = h["time"]
    late = t >= 20e-6
    print("%-8s u_x at %.0f us: %.6e m (%+.4f %% of the static value); range over t >= 20 us: "
          "%.4e ... %.4e m" % (name, 1e6 * t[-1], h["probe_ux"][-1],
                               100 * (h["probe_ux"][-1] / u_exact - 1), h["probe_ux"][late].min(),
                               h["probe_ux"][late].max()))
