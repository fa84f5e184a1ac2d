#!/usr/bin/env python3
"""Double cantilever beam (options/dcb_uniform.opts, options/dcb.opts): the stress intensity factor at rest on uniform grids
of 4, 2, 1 and 0.5 mm and on refined grids (2 / 1 mm, 2 / 1 / 0.5 mm), K_I by VCCT and by the
J-integral, against wall time. The converged value is the Richardson extrapolation of the
uniform 2, 1 and 0.5 mm VCCT values (observed order from the three); the beam-on-elastic-
foundation value 2 sqrt(3) F (a + 0.64 h) / (B h^(3/2)) and the paper's Eq. 17,
2 sqrt(3) F (a + 3 H / 2) / H^(3/2) with H the arm height, are printed beside it. Writes a
Markdown table to stdout, WORK/dcb_study.csv and docs/img/dcb_speed_error.png. Cost is the
run's CPU time (summary.json cpu_seconds; on one rank the wall time of an idle machine): the
study takes about half an hour, and other work sharing the machine would skew wall times.

Usage: /usr/bin/python3 runs/study_dcb.py [--gimp build/gimp] [--work DIR] [--no-run]
"""
import csv
import math
import os

import series

ROOT = series.ROOT
SCENE = os.path.join(ROOT, "options", "dcb.opts")
UNIFORM = os.path.join(ROOT, "options", "dcb_uniform.opts")
RUNS = [  # name, scene, extra options, kind
    ("uniform 4 mm", UNIFORM, ["-gimp_h", "4e-3"], "uniform"),
    ("uniform 2 mm", UNIFORM, ["-gimp_h", "2e-3"], "uniform"),
    ("uniform 1 mm", UNIFORM, ["-gimp_h", "1e-3"], "uniform"),
    ("2 levels 2/1 mm", SCENE, [], "refined"),
    ("3 levels 2/1/0.5 mm", SCENE, ["-gimp_levels", "3", "-gimp_level2_box", "0.045,0.007,0.055,0.017",
                             "-gimp_level2_ratio", "2"], "refined"),
    ("uniform 0.5 mm", UNIFORM, ["-gimp_h", "0.5e-3"], "uniform"),
]
U4, U2, U1, L2, L3, U05 = range(6)
# Every grid runs the same physical time at the same dt (0.1 us, the paper's), long enough that
# the slowest grid is at rest (kinetic / strain energy below 1e-6 from the previous history row
# on): the wall times then compare equal work, not the rest criterion's luck of the draw.
T_END = 0.015  # [s]
COMMON = ["-gimp_static_tol", "0", "-ts_max_time", str(T_END), "-ts_max_steps", "1000000"]
F, A, H, B = 4e-4, 0.05, 0.012, 1e-3  # load [N], crack length, arm height, thickness [m]


def beam():
    return 2 * math.sqrt(3) * F * (A + 0.64 * H) / (B * H ** 1.5)


def eq17():
    # The paper's form: no thickness (per unit thickness) and a + 3H/2.
    return 2 * math.sqrt(3) * F * (A + 1.5 * H) / (B * H ** 1.5)


def richardson(k1, k2, k3):
    """Limit of k(h) = k0 + c h^p from h, h/2, h/4."""
    r = (k1 - k2) / (k2 - k3)
    p = math.log(r, 2) if r > 0 else float("nan")
    return k3 + (k3 - k2) / (r - 1), p


def settled(path):
    """Kinetic / strain energy at the last history row, and the relative change of K_I (VCCT)
    over the last 2 ms: how far from rest the run ended."""
    with open(path) as f:
        h = list(csv.DictReader(f))
    key = [k for k in h[0] if k.endswith("_KI_vcct")][0]
    last = h[-1]
    t0 = float(last["time"]) - 2e-3
    back = min(h, key=lambda r: abs(float(r["time"]) - t0))
    return (float(last["kinetic"]) / float(last["strain"]),
            float(last[key]) / float(back[key]) - 1)


def main():
    a = series.parse_args("dcb_study")
    rows = []
    for name, kind, out, s in series.run_series(a, RUNS, COMMON):
        c = s["cracks"][0]
        ke_u, drift = settled(os.path.join(out, "history.csv"))
        rows.append(dict(name=name, kind=kind, particles=s["particles"], steps=s["steps"],
                         wall=s["wall_seconds"], cpu=s["cpu_seconds"], status=s["status"],
                         KI_vcct=c["KI_vcct"], KI_J=c["KI_J"], ke_u=ke_u, drift=drift))
    k0, order = richardson(rows[U2]["KI_vcct"], rows[U1]["KI_vcct"], rows[U05]["KI_vcct"])
    for r in rows:
        r["err_vcct"] = r["KI_vcct"] / k0 - 1
        r["err_J"] = r["KI_J"] / k0 - 1
        r["vcct_J"] = r["KI_vcct"] / r["KI_J"] - 1
    print("Converged K_I (Richardson, uniform 2/1/0.5 mm VCCT, observed order %.2f): %.4f Pa m^0.5"
          % (order, k0))
    print("Beam on elastic foundation: %.4f Pa m^0.5 (%+.2f %% from the converged value); "
          "the paper's Eq. 17 (a + 3H/2): %.4f (%+.2f %%)\n" %
          (beam(), 100 * (beam() / k0 - 1), eq17(), 100 * (eq17() / k0 - 1)))
    print("| grid | particles | steps | wall [s] | CPU [s] | KE / U at end | K change, last 2 ms | "
          "K_I VCCT | K_I J | VCCT error | J error | VCCT / J - 1 |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print("| %s | %d | %d | %.1f | %.1f | %.1e | %+.1e | %.4f | %.4f | %+.2f %% | %+.2f %% | "
              "%+.2f %% |" % (r["name"], r["particles"], r["steps"], r["wall"], r["cpu"], r["ke_u"],
                              r["drift"], r["KI_vcct"], r["KI_J"], 100 * r["err_vcct"],
                              100 * r["err_J"], 100 * r["vcct_J"]))
    for lv, un in ((rows[L2], rows[U1]), (rows[L3], rows[U05])):
        print("\n%s against %s (its finest cell): K_I VCCT %+.3f %%, J %+.3f %%, CPU time %.2f "
              "times less (wall %.2f)" % (lv["name"], un["name"],
                                          100 * (lv["KI_vcct"] / un["KI_vcct"] - 1),
                                          100 * (lv["KI_J"] / un["KI_J"] - 1),
                                          un["cpu"] / lv["cpu"], un["wall"] / lv["wall"]))
    os.makedirs(a.work, exist_ok=True)
    with open(os.path.join(a.work, "dcb_study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for kind, mark in (("uniform", "o-"), ("refined", "s")):
        pts = [r for r in rows if r["kind"] == kind]
        ax.loglog([r["cpu"] for r in pts], [abs(r["err_vcct"]) for r in pts], mark,
                  label=kind + " (VCCT)")
        ax.loglog([r["cpu"] for r in pts], [abs(r["err_J"]) for r in pts], mark[0],
                  mfc="none", label=kind + " (J)")
        for r in pts:
            ax.annotate(r["name"], (r["cpu"], abs(r["err_vcct"])), fontsize=7, xytext=(4, 4),
                        textcoords="offset points")
    ax.set_xlabel("CPU time [s] (1 rank, %g ms at dt 0.1 us)" % (1e3 * T_END))
    ax.set_ylabel("|K_I / converged - 1|")
    ax.set_title("DCB at rest: K_I error against CPU time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "img", "dcb_speed_error.png"), dpi=120)


if __name__ == "__main__":
    main()
