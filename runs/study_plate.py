#!/usr/bin/python3
"""Plate with a hole (paper section 4.4): the static stress concentration at the top of the hole
on the three-level grid and on uniform grids, and the paper's 4000-step dynamic run; the
measurements of docs/validation.md, section "Plate with a hole".

Usage: /usr/bin/python3 runs/study_plate.py --gimp build/gimp --root . --work WORK [--quick]

Static runs (damped: -gimp_damping 3e5 -ts_max_steps 20000, 200 us), into WORK/<name>, on
  3level      options/plate.opts (1.0 / 0.5 / 0.25 mm)
  h1.0 ...    options/plate_uniform.opts with -gimp_h 1e-3, 0.5e-3, (0.25e-3, the scene's)
each with -gimp_flip 0 (static_pic_<grid>: PIC, comes to rest) and -gimp_flip 1
(static_flip1_<grid>: the default FLIP, which keeps a slow oscillation that the grid damping
does not remove). Dynamic runs as in the paper (d = 1000 1/s, dt = 10 ns, 4000 steps = 40 us):
  paper_3level, paper_h0.25
and two static PIC runs with finer levels at the top of the hole (static_pic_4level: + 0.125 mm,
static_pic_5level: + 0.0625 mm). Writes WORK/plate.csv and prints the markdown table. The probe "hole_top" follows the particle
nearest to (0, a); its sxx / p is compared with Kirsch's infinite-plate solution at that
particle's initial position (r, theta) and with the finite-width gross-section value of a long
strip, (2 + (1 - d/W)^3) / (1 - d/W) = 3.014 for d/W = 1/15 (docs/reference.md, section 3.2).
--no-run tabulates the outputs already in WORK. --quick runs 2000 static steps (a smoke test of the script, not the documented numbers).
"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import gimptest  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--gimp", required=True)
ap.add_argument("--root", required=True)
ap.add_argument("--work", required=True)
ap.add_argument("--quick", action="store_true")
ap.add_argument("--no-run", action="store_true", help="tabulate the outputs already in WORK")
args = ap.parse_args()
args.gimp, args.root, args.work = (os.path.abspath(p) for p in (args.gimp, args.root, args.work))
args.mpiexec = "mpiexec"
os.makedirs(args.work, exist_ok=True)

P, A, D_OVER_W = 10e6, 2e-3, 4.0 / 60.0
KT_WIDTH = (2 + (1 - D_OVER_W) ** 3) / (1 - D_OVER_W)
STATIC = ["-gimp_damping", "3e5", "-ts_max_steps", "2000" if args.quick else "20000",
          "-gimp_output_interval", "0", "-gimp_monitor_interval", "0",
          "-gimp_history_interval", "100"]
PAPER = ["-ts_max_steps", "4000", "-gimp_output_interval", "0", "-gimp_monitor_interval", "0"]
GRIDS = [("3level", "options/plate.opts", [], "3 levels 1.0 / 0.5 / 0.25 mm"),
         ("h1.0", "options/plate_uniform.opts", ["-gimp_h", "1e-3"], "uniform 1.0 mm"),
         ("h0.5", "options/plate_uniform.opts", ["-gimp_h", "0.5e-3"], "uniform 0.5 mm"),
         ("h0.25", "options/plate_uniform.opts", [], "uniform 0.25 mm")]
RUNS = []
for flip, tag in (("0", "pic"), ("1", "flip1")):
    for g, opts, extra, label in GRIDS:
        RUNS.append(("static_%s_%s" % (tag, g), opts, STATIC + extra + ["-gimp_transfer", "flip", "-gimp_flip", flip], label,
                     "static, FLIP %s" % flip))
# Finer levels around the hole (PIC, static): 0.125 mm and 0.0625 mm at the top of the hole.
L3 = ["-gimp_levels", "4", "-gimp_level3_box", "-0.5e-3,-0.5e-3,3e-3,3e-3", "-gimp_level3_ratio", "2"]
L4 = ["-gimp_levels", "5", "-gimp_level3_box", "-0.5e-3,-0.5e-3,3e-3,3e-3", "-gimp_level3_ratio", "2",
      "-gimp_level4_box", "-0.25e-3,1.5e-3,1e-3,2.75e-3", "-gimp_level4_ratio", "2"]
RUNS.append(("static_pic_4level", "options/plate.opts", STATIC + L3 + ["-gimp_transfer", "flip", "-gimp_flip", "0"],
             "4 levels, + 0.125 mm on [-0.5, 3]² mm", "static, FLIP 0"))
RUNS.append(("static_pic_5level", "options/plate.opts", STATIC + L4 + ["-gimp_transfer", "flip", "-gimp_flip", "0"],
             "5 levels, + 0.0625 mm on [-0.25, 1] × [1.5, 2.75] mm", "static, FLIP 0"))
for g, opts, extra, label in (GRIDS[0], GRIDS[3]):
    RUNS.append(("paper_%s" % g, opts, PAPER + extra, label, "paper (dynamic)"))


def kirsch_sxx(x, y):
    """sigma_xx / p of the infinite plate with a hole of radius A under remote sxx = p."""
    r, th = math.hypot(x, y), math.atan2(y, x)
    q = (A / r) ** 2
    srr = 0.5 * (1 - q) + 0.5 * (1 - 4 * q + 3 * q * q) * math.cos(2 * th)
    stt = 0.5 * (1 + q) - 0.5 * (1 + 3 * q * q) * math.cos(2 * th)
    srt = -0.5 * (1 + 2 * q - 3 * q * q) * math.sin(2 * th)
    c, s = math.cos(th), math.sin(th)
    return srr * c * c + stt * s * s - 2 * srt * s * c


rows = []
for name, opts, extra, grid, kind in RUNS:
    out = os.path.join(args.work, name)
    if not args.no_run:
        gimptest.run(args, opts, extra, outdir=out)
    s = gimptest.summary(out)
    h = gimptest.history(out)
    pr = s["probes"]["hole_top"]
    x0, y0 = pr["x0"]
    kt = pr["stress"][0] / P
    # Change of the probe stress over the last quarter of the run (is it at rest?).
    n = len(h["time"])
    k3 = h["hole_top_sxx"][(3 * n) // 4] / P
    half = [v / P for v in h["hole_top_sxx"][n // 2:]]
    kk = kirsch_sxx(x0, y0)
    rows.append({
        "name": name, "grid": grid, "kind": kind, "particles": s["particles"],
        "steps": s["steps"], "time_us": 1e6 * s["time"], "wall": s["wall_seconds"],
        "x0_mm": 1e3 * x0, "y0_mm": 1e3 * y0, "r_mm": 1e3 * math.hypot(x0, y0),
        "kt": kt, "kirsch_r": kk, "kirsch_r_fw": kk * KT_WIDTH / 3.0,
        "kt_change_last_quarter": kt - k3,
        "kt_min_2nd_half": min(half), "kt_max_2nd_half": max(half),
        "ke_over_strain": s["energy"]["kinetic"] / s["energy"]["strain"],
        "far_sxx": s["probes"]["far"]["stress"][0] / P,
        "kt_edge": s["measures"].get("kt_edge") if s["measures"].get("kt_edge") is not None
        else float("nan"),
    })

with open(os.path.join(args.work, "plate.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)

print("Finite-width gross-section Kt (long strip, d/W = 1/15): %.4f\n" % KT_WIDTH)
print("kt_edge: summary.json measures.kt_edge (-gimp_hole_measure), the linear extrapolation of "
      "the hoop stress to the edge on the 90-degree ray\n")
print("| run | grid | particles | steps (time) | wall [s] | probe particle x0, y0 [mm] (r) | "
      "σxx/p at the probe | min … max over the second half | Kirsch at the probe's r, θ | "
      "Kirsch × 3.014/3 | kt_edge | change over the last quarter | kinetic / strain at the end |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for r in rows:
    print("| %s | %s | %d | %d (%.0f µs) | %.1f | %.4f, %.4f (%.4f) | %.4f | %.2f … %.2f | %.4f | "
          "%.4f | %s | %+.1e | %.1e |" %
          (r["kind"], r["grid"], r["particles"], r["steps"], r["time_us"], r["wall"], r["x0_mm"],
           r["y0_mm"], r["r_mm"], r["kt"], r["kt_min_2nd_half"], r["kt_max_2nd_half"],
           r["kirsch_r"], r["kirsch_r_fw"],
           "null" if math.isnan(r["kt_edge"]) else "%.4f" % r["kt_edge"],
           r["kt_change_last_quarter"], r["ke_over_strain"]))
print("\nfar probe (20, 20) mm, sxx / p: " +
      ", ".join("%s %.4f" % (r["name"], r["far_sxx"]) for r in rows))
