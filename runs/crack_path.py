#!/usr/bin/env python3
"""Plot the path of the crack that grows toward a hole (options/crack_hole_path.opts) at h and
h/2 from tests/check_crack_path.py's paths.csv: docs/img/crack_hole_path.png.

    /usr/bin/python3 tests/check_crack_path.py --gimp build/gimp --root . --work /tmp/crack_path
    /usr/bin/python3 runs/crack_path.py /tmp/crack_path
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HOLE = (28.0, 59.0, 5.0)  # mm, as in the scene


def main():
    work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/crack_path"
    paths = {}
    with open(os.path.join(work, "paths.csv")) as f:
        for r in csv.DictReader(f):
            paths.setdefault(r["run"], []).append((1e3 * float(r["x"]), 1e3 * float(r["y"])))
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    t = [2 * math.pi * k / 200 for k in range(201)]
    ax.fill([HOLE[0] + HOLE[2] * math.cos(a) for a in t], [HOLE[1] + HOLE[2] * math.sin(a) for a in t],
            color="0.85", label="hole")
    ax.plot([0, 12], [52, 52], "k-", lw=2, label="initial crack")
    for (name, path), style in zip(sorted(paths.items()), ("o-", "s--")):
        ax.plot([p[0] for p in path], [p[1] for p in path], style, ms=3,
                label="grown, finest cell %s" % ("1 mm" if name == "h" else "0.5 mm"))
    ax.set_aspect("equal")
    ax.set_xlim(0, 36)
    ax.set_ylim(48, 66)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("Edge crack growing toward a hole (maximum hoop stress)")
    ax.legend(loc="upper left", fontsize=8)
    out = os.path.join(ROOT, "docs", "img", "crack_hole_path.png")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("wrote", out)


if __name__ == "__main__":
    main()
