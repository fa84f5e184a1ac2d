#!/usr/bin/env python3
"""Speed against error for a 3D crack front: the penny-shaped crack of options/penny3d.opts
(radius a = 10 mm, a quarter of a 96 mm cube, remote tension, damped to rest) on uniform grids
and on levels refined around the front. The error is that of K at the front points against the
infinite body's K_I = 2 sigma sqrt(a / pi): K from G (sqrt(G E'), the domain integral) and K_I by
the interaction integral, each as the mean and the worst over the quarter of the front. Two
series: the front integrals' tube 6 finest cells on every grid (it shrinks with the cell), and
the tube fixed at 6 mm = 0.6 a on the grids where that is at least 2 cells (the domain integral's
own convergence: the domain stays, the field inside it is refined). Writes a Markdown table to
stdout (costs in CPU seconds, which other work on the machine does not inflate) and
docs/img/speed_error_penny3d.png.

Usage: /usr/bin/python3 runs/speed_error_penny3d.py [--gimp build/gimp] [--work DIR] [--no-run]
(about 30 minutes of CPU on one core: the uniform 2 mm grid and the five levels take most of it)
"""
import math
import os

import series

ROOT = series.ROOT
SCENE = os.path.join(ROOT, "options", "penny3d.opts")
E, NU, SIGMA, A = 2.3e9, 0.3, 1e6, 0.01
K0 = 2 * SIGMA * math.sqrt(A / math.pi)
L1 = ["-gimp_level1_box", "0,0,-0.016,0.024,0.024,0.016", "-gimp_level1_ratio", "2"]  # the scene's
L2 = ["-gimp_level2_box", "0,0,-0.008,0.02,0.02,0.008", "-gimp_level2_ratio", "2"]
L3 = ["-gimp_level3_box", "0,0,-0.006,0.014,0.014,0.006", "-gimp_level3_ratio", "2"]
L4 = ["-gimp_level4_box", "0,0,-0.003,0.013,0.013,0.003", "-gimp_level4_ratio", "2"]
GRIDS = [  # name, extra options on the scene without levels, (kind, finest cell [m])
    ("uniform 4 mm", ["-gimp_h", "4e-3"], ("uniform", 4e-3)),
    ("uniform 2 mm", ["-gimp_h", "2e-3"], ("uniform", 2e-3)),
    ("3 levels 8/4/2 mm", ["-gimp_levels", "3"] + L1 + L2, ("refined", 2e-3)),
    ("4 levels to 1 mm (the scene)", ["-gimp_levels", "4"] + L1 + L2 + L3, ("refined", 1e-3)),
    ("5 levels to 0.5 mm", ["-gimp_levels", "5"] + L1 + L2 + L3 + L4, ("refined", 5e-4)),
]
TUBE = 6e-3  # the fixed tube radius of the second series [m] (the scene's own)


def runs():
    """(name, extra options, (kind, finest cell, tube radius)) of both series; a grid whose 6
    cells are 6 mm (the scene's 1 mm) is run once and belongs to both."""
    out = [(n, e, (k[0], k[1], 6 * k[1])) for n, e, k in GRIDS]
    out += [(n, e, (k[0], k[1], TUBE)) for n, e, k in GRIDS
            if TUBE >= 2 * k[1] and abs(TUBE - 6 * k[1]) > 1e-12]
    return out


def base_scene(work):
    """The scene's options file without its levels (each run gives its own)."""
    path = os.path.join(work, "penny3d_base.opts")
    os.makedirs(work, exist_ok=True)
    with open(SCENE) as f, open(path, "w") as g:
        for line in f:
            if not line.startswith("-gimp_level"):
                g.write(line)
    return path


def errors(summary):
    """(mean, worst) of K from G and of K_I over the front points, relative to K0."""
    Ep = E / (1 - NU * NU)
    front = summary["cracks"][0]["front"]
    eg = [math.sqrt(max(f["G"], 0.0) * Ep) / K0 - 1 for f in front]
    ei = [f["KI"] / K0 - 1 for f in front]
    return (sum(eg) / len(eg), max(eg, key=abs), sum(ei) / len(ei), max(ei, key=abs))


def main():
    a = series.parse_args("speed_error_penny3d")
    base = base_scene(a.work)
    rows = []
    todo = [(n, base, e + ["-gimp_crack_j_radius", repr(k[2])], k) for n, e, k in runs()]
    for name, kind, _, s in series.run_series(a, todo):
        rows.append((name, kind, s["particles"], s["steps"], s["cpu_seconds"], errors(s)))
    print("| grid | finest cell | a / h | tube | particles | steps | CPU [s] | K(G) mean |"
          " K(G) worst | K_I mean | K_I worst |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, kind, n, st, w, e in rows:
        print("| %s | %g mm | %g | %g mm (%g cells) | %d | %d | %.1f | %+.2f %% | %+.2f %% |"
              " %+.2f %% | %+.2f %% |" %
              (name, 1e3 * kind[1], A / kind[1], 1e3 * kind[2], kind[2] / kind[1], n, st, w,
               100 * e[0], 100 * e[1], 100 * e[2], 100 * e[3]))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for kind, fixed, mk in (("uniform", False, "o-"), ("refined", False, "s-"),
                            ("refined", True, "^-")):
        sel = [r for r in rows if r[1][0] == kind and
               (abs(r[1][2] - TUBE) < 1e-12 if fixed else abs(r[1][2] - 6 * r[1][1]) < 1e-12)]
        label = "uniform grids" if kind == "uniform" else "levels around the front"
        label += ", tube 6 mm" if fixed else ", tube 6 cells"
        ax.loglog([r[4] for r in sel], [abs(r[5][1]) for r in sel], mk, label=label + ", worst")
        ax.loglog([r[4] for r in sel], [abs(r[5][0]) for r in sel], mk, alpha=0.5,
                  label=label + ", mean")
    ax.set_xlabel("CPU time, one core [s]")
    ax.set_ylabel(r"$|K(G) / K_I^{exact} - 1|$ along the front")
    ax.set_title("3D penny-shaped crack under tension", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(ROOT, "docs", "img", "speed_error_penny3d.png")
    fig.savefig(path, dpi=110)
    print("wrote", path)


if __name__ == "__main__":
    main()
