#!/usr/bin/env python3
"""Speed against error in 3D: the half-space under a circular load (options/halfspace3d.opts) on
uniform grids and on two, three and four levels refined around the load. The error is that of
sigma_z on the axis at z = a and z = 2a, read from the particles as tests/check_halfspace3d.py
reads it (tests/halfspace_axis.py), against Boussinesq's solution. Every run ramps the load over
0.2 s and is damped to rest by t = 1 s. Writes a Markdown table to stdout and
docs/img/speed_error3d.png.

Usage: /usr/bin/python3 runs/speed_error3d.py [--gimp build/gimp] [--work DIR] [--no-run]
(about 6 minutes on one core; the uniform 0.25 m grid takes most of it)
"""
import os
import sys

import series

ROOT = series.ROOT
sys.path.insert(0, os.path.join(ROOT, "tests"))
import gimptest  # noqa: E402
import halfspace_axis  # noqa: E402

SCENE = os.path.join(ROOT, "options", "halfspace3d.opts")
L1 = ["-gimp_level1_box", "0,0,-4,4,4,0", "-gimp_level1_ratio", "2"]  # as in the scene
L2 = ["-gimp_level2_box", "0,0,-3,2,2,0", "-gimp_level2_ratio", "2"]
L3 = ["-gimp_level3_box", "0,0,-2.5,1.5,1.5,0", "-gimp_level3_ratio", "2"]
RUNS = [  # name, extra options on the scene without levels, (kind, finest particle spacing [m])
    ("uniform 1 m", [], ("uniform", 0.5)),
    ("uniform 0.5 m", ["-gimp_h", "0.5"], ("uniform", 0.25)),
    ("uniform 0.25 m", ["-gimp_h", "0.25"], ("uniform", 0.125)),
    ("2 levels 1/0.5 m", ["-gimp_levels", "2"] + L1, ("refined", 0.25)),
    ("3 levels 1/0.5/0.25 m", ["-gimp_levels", "3"] + L1 + L2, ("refined", 0.125)),
    ("4 levels 1/0.5/0.25/0.125 m", ["-gimp_levels", "4"] + L1 + L2 + L3, ("refined", 0.0625)),
]


def base_scene(work):
    """The scene's options file without its levels (each run gives its own)."""
    path = os.path.join(work, "halfspace3d_base.opts")
    os.makedirs(work, exist_ok=True)
    with open(SCENE) as f, open(path, "w") as g:
        for line in f:
            if not line.startswith("-gimp_level"):
                g.write(line)
    return path


def main():
    a = series.parse_args("speed_error3d")
    base = base_scene(a.work)
    runs = [(n, base, e + ["-gimp_particle_dump", os.path.join(a.work, "dump%d.csv" % i)], k)
            for i, (n, e, k) in enumerate(RUNS)]
    rows = []
    for i, (name, kind, out, s) in enumerate(series.run_series(a, runs)):
        d = gimptest.read_csv(os.path.join(a.work, "dump%d.csv" % i))
        spacing = RUNS[i][2][1]
        errs = []
        for z0 in (1.0, 2.0):
            s0, _ = halfspace_axis.axis_value(d, z0, spacing, max(0.5, 2.5 * spacing))
            errs.append(s0 / halfspace_axis.exact(z0) - 1)
        rows.append((name, kind[0], s["particles"], s["steps"], s["wall_seconds"], errs))
    print("| grid | particles | steps | wall [s] | error at z = a | error at z = 2a |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, _, n, st, w, e in rows:
        print("| %s | %d | %d | %.1f | %+.2f %% | %+.2f %% |" % (name, n, st, w, 100 * e[0],
                                                            100 * e[1]))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for kind, mk in (("uniform", "o-"), ("refined", "s-")):
        sel = [r for r in rows if r[1] == kind]
        for j, z in enumerate(("a", "2a")):
            ax.loglog([r[4] for r in sel], [abs(r[5][j]) for r in sel], mk,
                      color="C%d" % (j + (2 if kind == "refined" else 0)),
                      label="%s, z = %s" % ("uniform grids" if kind == "uniform" else
                                            "levels around the load", z))
    ax.set_xlabel("wall time, one core [s]")
    ax.set_ylabel(r"$|\sigma_z / \sigma_z^{exact} - 1|$ on the axis")
    ax.set_title("3D half-space under a circular load", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(ROOT, "docs", "img", "speed_error3d.png")
    fig.savefig(path, dpi=110)
    print("wrote", path)


if __name__ == "__main__":
    main()
