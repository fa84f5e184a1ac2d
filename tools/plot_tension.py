#!/usr/bin/python3
"""Plots of particle domain tracking on the uniaxial tension block (options/tension.opts, the
paper's section 4.1).

Usage: /usr/bin/python3 tools/plot_tension.py --gimp build/gimp [--work /tmp/tension_plot]
                                              [--outdir docs/img] [--no-run]

Runs the scene for -gimp_tracking none, strain, stretch and corners with particle output every
10 steps (-gimp_output_interval 10) into <work>/<mode>; the runs without corners stop with
exit 3 when the torn-off end leaves the grid, and what they wrote up to then is plotted.
--no-run plots what <work> already holds. Writes:

  tension_particles.png  the particles of the strain and the corners runs drawn as the
                         rectangles they occupy (strain: [x - l, x + l]; corners: the
                         axis-aligned rectangle spanned by the four tracked corners), coloured
                         by sigma_xx, at the output step where the strain run first separates,
                         at 15 ns, at 20 ns (the time of the paper's Fig. 7(a)) and at the end
                         of each run; the dashed outline is the initial block, the dots the
                         material points.
  tension_history.png    the largest gap between former neighbours (in particle sizes) and
                         the engineering strain of the particles' extent along x against time
                         for the four modes (history.csv columns separation and strain_x).
"""
import argparse
import csv
import json
import os
import subprocess

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODES = ("none", "strain", "stretch", "corners")
UM, GPA = 1e6, 1e-9

ap = argparse.ArgumentParser()
ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
ap.add_argument("--work", default="/tmp/tension_plot")
ap.add_argument("--outdir", default=os.path.join(ROOT, "docs", "img"))
ap.add_argument("--no-run", action="store_true")
a = ap.parse_args()
work = os.path.abspath(a.work)
os.makedirs(work, exist_ok=True)
os.makedirs(a.outdir, exist_ok=True)

if not a.no_run:
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    for mode in MODES:
        cmd = [os.path.abspath(a.gimp), "-options_file", os.path.join(ROOT, "runs", "tension.opts"),
               "-gimp_tracking", mode, "-gimp_output_interval", "10",
               "-gimp_output_dir", os.path.join(work, mode)]
        p = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True)
        if p.returncode not in (0, 3):
            raise SystemExit("gimp failed (exit %d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr))
        print("%-8s exit %d" % (mode, p.returncode))


def history(mode):
    with open(os.path.join(work, mode, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("step", "time", "separation",
                                                                "strain_x")}


def summary(mode):
    with open(os.path.join(work, mode, "summary.json")) as f:
        return json.load(f)


hist = {m: history(m) for m in MODES}
summ = {m: summary(m) for m in MODES}
thr = 0.05  # -gimp_separation_threshold (default)
dt = summ["corners"]["dt"]

# ---- Particles as their tracked rectangles ------------------------------------------------
h5 = {m: h5py.File(os.path.join(work, m, "fields.h5"), "r") for m in ("strain", "corners")}
steps = {m: sorted(int(k.split("_")[1]) for k in h5[m]["particles"]) for m in h5}
hs = hist["strain"]
sep_step = int(hs["step"][np.argmax(hs["separation"] > thr)])


def nearest(mode, step):
    return min(steps[mode], key=lambda s: abs(s - step))


rows = [("strain separates", {m: nearest(m, sep_step) for m in h5}),
        ("15 ns", {m: nearest(m, round(15e-9 / dt)) for m in h5}),
        ("20 ns", {m: nearest(m, round(20e-9 / dt)) for m in h5}),
        ("end of run", {m: steps[m][-1] for m in h5})]
norm = matplotlib.colors.Normalize(-40, 100)
cmap = plt.get_cmap("turbo")
dom = summ["corners"]["levels"][0]["box"]
fig, axes = plt.subplots(len(rows), 2, figsize=(13, 1.45 * len(rows) + 0.6), sharex=True,
                         sharey=True, layout="constrained")
for i, (label, at) in enumerate(rows):
    for j, mode in enumerate(("strain", "corners")):
        ax = axes[i, j]
        g = h5[mode]["particles"]["step_%08d" % at[mode]]
        x, sxx = g["x"][:], g["stress"][:, 0]
        if "corners" in g:
            c = g["corners"][:]
            lo = np.stack([c[:, 0::2].min(1), c[:, 1::2].min(1)], 1)
            hi = np.stack([c[:, 0::2].max(1), c[:, 1::2].max(1)], 1)
        else:
            lo, hi = x - g["l"][:], x + g["l"][:]
        pc = PatchCollection([Rectangle(p * UM, *((q - p) * UM)) for p, q in zip(lo, hi)],
                             cmap=cmap, norm=norm, edgecolor="k", linewidth=0.3)
        pc.set_array(sxx * GPA)
        ax.add_collection(pc)
        ax.plot(x[:, 0] * UM, x[:, 1] * UM, "k.", ms=1)
        ax.add_patch(Rectangle((0, 0), 40, 10, fill=False, ls="--", lw=0.7, ec="0.4"))
        t = at[mode] * dt
        hm = hist[mode]
        k = np.argmin(abs(hm["step"] - at[mode]))
        ax.set_title("%s tracking, %s: t = %.1f ns, strain_x %.3f, gap %.2g l" %
                     (mode, label, t * 1e9, hm["strain_x"][k], hm["separation"][k]), fontsize=9)
        ax.set_xlim(dom[0] * UM, dom[2] * UM)
        ax.set_ylim(-3, 13)
        ax.set_aspect("equal")
        if j == 0:
            ax.set_ylabel("y [µm]")
        if i == len(rows) - 1:
            ax.set_xlabel("x [µm]")
fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes, shrink=0.8,
             aspect=30, label="σxx [GPa]")
fig.suptitle("Uniaxial tension, 55 GPa ramped over 10 ns then held (options/tension.opts): "
             "particles as their tracked rectangles")
out = os.path.join(a.outdir, "tension_particles.png")
fig.savefig(out, dpi=110)
print("wrote %s" % out)

# ---- Separation and strain against time ---------------------------------------------------
fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.5, 7), sharex=True)
for c, mode in zip(("C0", "C1", "C2", "C3"), MODES):
    hm, s = hist[mode], summ[mode]
    t = hm["time"] * 1e9
    ss = s["measures"]["separation_strain"]
    lab = "%s (%s)" % (mode, "separates at strain %.3f" % ss if ss is not None else
                       "no separation up to strain %.3f" % s["measures"]["max_strain"])
    if s["status"] != "completed":
        lab += ", leaves the grid at %.1f ns" % (s["time"] * 1e9)
    a1.semilogy(t, np.maximum(hm["separation"], 1e-16), color=c, label=lab)
    a2.plot(t, hm["strain_x"], color=c, label=mode)
    k = np.argmax(hm["separation"] > thr)
    if hm["separation"][k] > thr:
        a1.plot(t[k], hm["separation"][k], "o", color=c)
        a2.plot(t[k], hm["strain_x"][k], "o", color=c)
a1.axhline(thr, color="k", ls=":", lw=0.8)
a1.text(0.3, thr * 1.5, "threshold %g" % thr, fontsize=8)
a1.set_ylim(1e-16, 1e2)  # corners: round-off gaps, those <= 1e-16 drawn at 1e-16
a1.set_ylabel("largest gap between former\nneighbours / particle size")
a1.legend(fontsize=7.5, loc="center right")
a2.set_ylim(0, 1.3)
a2.axvline(10, color="0.5", ls="--", lw=0.8)
a2.text(10.2, 1.2, "full load (55 GPa) from 10 ns", fontsize=8)
a2.set_xlabel("t [ns]")
a2.set_ylabel("engineering strain of the\nparticles' extent along x")
a2.legend(fontsize=8, loc="upper left")
for ax in (a1, a2):
    ax.grid(True, which="major", ls=":", lw=0.5)
a1.set_title("Particle domain tracking on the tension block (dots: first above the threshold)",
             fontsize=10)
fig.tight_layout()
out = os.path.join(a.outdir, "tension_history.png")
fig.savefig(out, dpi=120)
print("wrote %s" % out)
