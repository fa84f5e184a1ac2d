#!/usr/bin/python3
"""Fixed-free bar, axial mode 1 (options/bar.opts, tests/check_bar.py): tip displacement against the
exact solution, and the total energy against time.

Usage: /usr/bin/python3 tools/plot_bar.py WORK/bar [-o docs/img/bar.png]

WORK/bar is the output directory tests/check_bar.py writes (history.csv and summary.json of the
run with -gimp_history_interval 2). Exact (docs/reference.md, section 1): u(x, t) = (v0 / omega)
sin(omega t) sin(beta x), beta = pi / 2L, omega = beta sqrt(E / rho), at the probe particle's
initial x. Also prints the per-period mean and range of (kinetic + strain) / E0 - 1.
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
ap.add_argument("outdir")
ap.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "img", "bar.png"))
a = ap.parse_args()

with open(os.path.join(a.outdir, "history.csv")) as f:
    rows = list(csv.DictReader(f))
with open(os.path.join(a.outdir, "summary.json")) as f:
    summ = json.load(f)
h = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
E, L, rho, v0 = 100.0, 25.0, 1.0, 0.1
beta = math.pi / (2 * L)
omega = beta * math.sqrt(E / rho)
T = 2 * math.pi / omega
x0 = summ["probes"]["tip"]["x0"][0]
t = h["time"]
exact = v0 / omega * np.sin(omega * t) * math.sin(beta * x0)
e = h["kinetic"] + h["strain"]
rel = e / e[0] - 1

fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True)
ax1.plot(t, exact, "k-", lw=2.5, alpha=0.35, label="exact, x = %.2f m" % x0)
ax1.plot(t, h["tip_ux"], "C0-", lw=1, label="gimp (h = 1 m, 2 x 2 particles/cell, dt = 0.01 s)")
ax1.set_ylabel("tip displacement u_x [m]")
ax1.set_ylim(-0.2, 0.26)
ax1.legend(fontsize=8, loc="upper center", ncol=2)
ax1.grid(True, lw=0.3)
ax1.set_title("Fixed-free bar, mode 1: E = 100 Pa, ρ = 1 kg/m³, L = 25 m, T = 10 s", fontsize=9)
ax2.plot(t, 100 * rel, "C1-", lw=0.8, label="(kinetic + strain) / E0 − 1")
means = []
for k in range(int(round(t[-1] / T))):
    m = (t >= k * T) & (t < (k + 1) * T)
    means.append(rel[m].mean())
    ax2.plot([k * T, (k + 1) * T], [100 * rel[m].mean()] * 2, "k-", lw=1.5,
             label="mean over each period" if k == 0 else None)
ax2.set_xlabel("time [s]")
ax2.set_ylabel("energy change [%]")
ax2.set_ylim(-0.75, 0.6)
ax2.legend(fontsize=8, loc="lower center", ncol=2)
ax2.grid(True, lw=0.3)
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(a.output)), exist_ok=True)
fig.savefig(a.output, dpi=110)
print("wrote", a.output)
print("E0 = %.6g J (exact rho v0^2 L / 4 = %.6g J)" % (e[0], rho * v0 ** 2 * L / 4))
print("(kinetic + strain) / E0 - 1: range %+.3e ... %+.3e; mean per period: %s" %
      (rel.min(), rel.max(), ", ".join("%+.2e" % m for m in means)))
err = h["tip_ux"] - exact
print("max |u_tip - exact| = %.3e m (%.2f %% of the amplitude %.5f m)" %
      (abs(err).max(), 100 * abs(err).max() / (v0 / omega * math.sin(beta * x0)),
       v0 / omega * math.sin(beta * x0)))
