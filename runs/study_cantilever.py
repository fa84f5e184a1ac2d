#!/usr/bin/python3
"""Large-deflection cantilever against the elastica: the table and the figure of
docs/validation.md, section "Large-deflection cantilever".

Usage: /usr/bin/python3 runs/study_cantilever.py --gimp build/gimp --root . --work WORK
           [--runs stretch:0.0125,corners:0.0125,...] [--write-docs]

Each run is options/cantilever.opts (P L^2/EI = 1) or options/cantilever4.opts (4) with
-gimp_tracking T and -gimp_h h (H/h cells through the thickness), into WORK/<scene>_<T>_<h>/,
with particle dumps of the initial and the final (at rest) state; a run whose final dump is
there already is not repeated. A tracking gimp refuses (exit 2) is left out of the table.
Measures as tests/check_cantilever.py (tests/elastica.py). Prints the markdown table; with
--write-docs it replaces the table between the markers of docs/validation.md and draws
docs/img/cantilever.png (rotation along the beam against the elastica, and its difference).
"""
import argparse
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import elastica  # noqa: E402
import gimptest  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--gimp", required=True)
ap.add_argument("--root", required=True)
ap.add_argument("--work", required=True)
ap.add_argument("--runs", default="stretch:0.0125,corners:0.0125,cpdi:0.0125,cpdi2:0.0125,"
                "corners:0.00625,cpdi2:0.00625")
ap.add_argument("--write-docs", action="store_true")
a = ap.parse_args()
a.gimp, a.root, a.work = (os.path.abspath(p) for p in (a.gimp, a.root, a.work))
os.makedirs(a.work, exist_ok=True)
H = 0.05
SCENES = (("cantilever", 1.0), ("cantilever4", 4.0))
BEGIN = "<!-- study_cantilever: table -->"
END = "<!-- /study_cantilever: table -->"


def gimp(scene, name, extra):
    cmd = [a.gimp, "-options_file", os.path.join(a.root, "options", scene + ".opts"),
           "-gimp_output_dir", os.path.join(a.work, name)] + extra
    return subprocess.run(cmd, cwd=a.work, capture_output=True, text=True)


def measure(scene, q, tracking, h):
    name = "%s_%s_%g" % (scene, tracking, h)
    d0 = os.path.join(a.work, name + "_initial.csv")
    d1 = os.path.join(a.work, name + "_final.csv")
    opts = ["-gimp_tracking", tracking, "-gimp_h", repr(h)]
    if not os.path.exists(d1):
        p = gimp(scene, name + "_initial", opts + ["-ts_max_steps", "0",
                                                   "-gimp_particle_dump", d0])
        if p.returncode == 2:
            print("left out %s: %s" % (name, p.stderr.strip()), file=sys.stderr)
            return None
        p = gimp(scene, name, opts + ["-gimp_particle_dump", d1])
        if p.returncode != 0:
            raise SystemExit("gimp failed (exit %d) on %s:\n%s" % (p.returncode, name, p.stderr))
    summ = gimptest.summary(os.path.join(a.work, name))
    s, x, y, th = elastica.centre_line(elastica.read_dump(d0), elastica.read_dump(d1), 0.0)
    ref = elastica.Elastica(q)
    tr, ur, vr = ref.at(s)
    err = np.degrees(th - tr)
    return {"scene": scene, "q": q, "tracking": tracking, "cells": round(H / h),
            "status": summ["status"], "steps": summ["steps"], "wall": summ["wall_seconds"],
            "du": 100 * ((x[-1] - s[-1]) / ur[-1] - 1), "dv": 100 * (y[-1] / vr[-1] - 1),
            "dtip": err[-1], "dmax": err[np.argmax(np.abs(err))], "s": s, "theta": th,
            "theta_ref": tr}


rows = []
for scene, q in SCENES:
    for spec in a.runs.split(","):
        tracking, h = spec.split(":")
        r = measure(scene, q, tracking, float(h))
        if r:
            rows.append(r)

table = ["| P L²/EI | tracking | cells through H | tip u − elastica | tip v − elastica | "
         "tip rotation − elastica | largest rotation difference | steps | status |",
         "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
for r in rows:
    table.append("| %g | `%s` | %d | %+.2f %% | %+.2f %% | %+.3f° | %+.3f° | %d | %s |" %
                 (r["q"], r["tracking"], r["cells"], r["du"], r["dv"], r["dtip"], r["dmax"],
                  r["steps"], r["status"]))
print("\n".join(table))

if a.write_docs:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for q, style in ((1.0, "-"), (4.0, "--")):
        ref = elastica.Elastica(q)
        ax[0].plot(ref.s, np.degrees(ref.theta), "k" + style, lw=2.5, alpha=0.35,
                   label="elastica, P L²/EI = %g" % q)
        for r in rows:
            if r["q"] == q:
                lab = "%s, H/h = %d, q = %g" % (r["tracking"], r["cells"], q)
                ax[0].plot(r["s"], np.degrees(r["theta"]), style, lw=1, label=lab)
                ax[1].plot(r["s"], np.degrees(r["theta"] - r["theta_ref"]), style, lw=1,
                           label=lab)
    ax[0].set(xlabel="s [m]", ylabel="rotation θ(s) [deg]", title="rotation along the beam")
    ax[1].set(xlabel="s [m]", ylabel="θ − θ_elastica [deg]", title="difference")
    ax[1].axhspan(-0.5, 0.5, color="0.9")
    ax[0].legend(fontsize=6)
    ax[1].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(a.root, "docs", "img", "cantilever.png"), dpi=120)
    path = os.path.join(a.root, "docs", "validation.md")
    with open(path) as f:
        text = f.read()
    i, j = text.index(BEGIN) + len(BEGIN), text.index(END)
    with open(path, "w") as f:
        f.write(text[:i] + "\n" + "\n".join(table) + "\n" + text[j:])
