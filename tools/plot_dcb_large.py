#!/usr/bin/env python3
"""The large-load double cantilever beam (options/dcb_large.opts, the paper's Fig. 20): the
particles at the last written step drawn as the quadrilaterals of their tracked corners,
coloured by sigma_yy, with the refined boxes; and K_I by VCCT and J and the opening of the
loaded end against time.

Usage: /usr/bin/python3 tools/plot_dcb_large.py RUN_DIR
Writes docs/img/dcb_large.png and prints the last history row's K_I, the mouth opening and the
smallest gap between the faces' particle edges (negative would be interpenetration).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
Y_CRACK, A = 0.012, 0.05  # crack plane and tip x [m]
BOXES = ((0.040, 0.002, 0.060, 0.022), (0.045, 0.007, 0.055, 0.017))


def main():
    run = sys.argv[1]
    with h5py.File(os.path.join(run, "fields.h5"), "r") as f:
        steps = sorted(f["particles"].keys())
        g = f["particles"][steps[-1]]
        x, X0 = np.array(g["x"]), np.array(g["X0"])
        corners, stress = np.array(g["corners"]), np.array(g["stress"])
    n = x.shape[0]
    quads = corners.reshape(n, 4, 2)
    syy = stress.reshape(n, -1)[:, 3]
    with open(os.path.join(run, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["time"]) for r in rows])
    kv = np.array([float(r["crack0_tip1_KI_vcct"]) for r in rows])
    kj = np.array([float(r["crack0_tip1_KI_J"]) for r in rows])
    # Mouth opening: the loaded end's particles just above and below the crack plane.
    end = X0[:, 0] < 1e-3
    upper = end & (X0[:, 1] > Y_CRACK) & (X0[:, 1] < Y_CRACK + 1e-3)
    lower = end & (X0[:, 1] < Y_CRACK) & (X0[:, 1] > Y_CRACK - 1e-3)
    mouth = (x[upper, 1] - X0[upper, 1]).mean() - (x[lower, 1] - X0[lower, 1]).mean()
    # Smallest gap between the faces: behind the tip, the lowest corner of the upper half's
    # first row minus the highest corner of the lower half's first row, column by column.
    face = X0[:, 0] < A
    up_row = face & (X0[:, 1] > Y_CRACK) & (X0[:, 1] < Y_CRACK + 0.3e-3)
    lo_row = face & (X0[:, 1] < Y_CRACK) & (X0[:, 1] > Y_CRACK - 0.3e-3)
    gaps = []
    for i in np.where(up_row)[0]:
        j = np.where(lo_row & (np.abs(X0[:, 0] - X0[i, 0]) < 1e-9))[0]
        if len(j):
            gaps.append(quads[i, :, 1].min() - quads[j[0], :, 1].max())
    print("%s at t = %.4g s: K_I VCCT %.6g, J %.6g Pa m^0.5; mouth opening %.4g mm; smallest "
          "face gap %.3g mm over %d columns" % (steps[-1], t[-1], kv[-1], kj[-1], 1e3 * mouth,
                                                1e3 * min(gaps), len(gaps)))

    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8, 7.5), gridspec_kw={"height_ratios": [1.5, 1]})
    pc = PolyCollection(1e3 * quads, array=syy / 1e3, cmap="coolwarm", edgecolors="none")
    lim = np.percentile(np.abs(syy), 99) / 1e3
    pc.set_clim(-lim, lim)
    ax.add_collection(pc)
    for b in BOXES:
        ax.plot(1e3 * np.array([b[0], b[2], b[2], b[0], b[0]]),
                1e3 * np.array([b[1], b[1], b[3], b[3], b[1]]), "k--", lw=0.7)
    ax.set_xlim(-2, 102)
    ax.set_ylim(-4, 28)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("DCB, F = 4 N, 3 levels 1 / 0.5 / 0.25 mm, corners, t = %.2f ms" % (1e3 * t[-1]))
    fig.colorbar(pc, ax=ax, label="sigma_yy [kPa]", shrink=0.8)
    bx.plot(1e3 * t, kv / 1e3, label="K_I VCCT")
    bx.plot(1e3 * t, kj / 1e3, "--", label="K_I J")
    bx.set_xlabel("t [ms]")
    bx.set_ylabel("K_I [kPa m^0.5]")
    bx.grid(True, alpha=0.3)
    bx.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "img", "dcb_large.png"), dpi=110)


if __name__ == "__main__":
    main()
