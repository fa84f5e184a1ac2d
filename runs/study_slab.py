#!/usr/bin/python3
"""Displacement-controlled slab (paper section 4.3, options/slab.opts): the measurements of
docs/validation.md, section "Penalty displacement conditions: the slab".

Usage: /usr/bin/python3 runs/study_slab.py --gimp build/gimp --root . --work WORK

Runs, each into WORK/<name>/:
  damped      the scene as it is (d = 1e6 1/s, automatic penalty, traction term on), with a
              particle dump (WORK/damped/particles.csv) and a history row every 10 steps;
  undamped    the same with -gimp_damping 0;
  alpha_<a>_<t>  the penalty sweep: -gimp_penalty a for a = 2.71e13 ... 2.71e16 Pa/m, with
              (t = on) and without (t = off, -gimp_penalty_traction false) the traction term.
              A value the input check refuses (exit 2) is recorded as refused.
Writes WORK/slab_runs.csv (one row per run) and prints the tables of the docs (markdown).
tools/plot_slab.py draws docs/img/slab.png from WORK/damped and WORK/undamped.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import gimptest  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--gimp", required=True)
ap.add_argument("--root", required=True)
ap.add_argument("--work", required=True)
a = ap.parse_args()
a.gimp, a.root, a.work = (os.path.abspath(p) for p in (a.gimp, a.root, a.work))
os.makedirs(a.work, exist_ok=True)

OPTS = "options/slab.opts"
E, NU, RHO, L, H, DELTA = 175.8e9, 0.28, 2710.0, 10e-3, 3e-3, 0.5e-3
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))
M = LAM + 2 * MU                       # P-wave modulus (plane strain)
EP = E / (1 - NU ** 2)                 # plane-strain modulus E'
HMIN, DT = 0.5e-3, 5e-9
ALPHAS = (2.71e13, 2.71e14, 2.71e15, 2.71e16)


def run(name, extra):
    out = os.path.join(a.work, name)
    cmd = [a.gimp, "-options_file", os.path.join(a.root, OPTS), "-gimp_output_dir", out] + extra
    p = subprocess.run(cmd, cwd=a.work, capture_output=True, text=True)
    if p.returncode == 2:
        return {"name": name, "status": "refused", "message": p.stderr.strip()}
    if p.returncode not in (0, 3):
        sys.stdout.write(p.stdout + p.stderr)
        raise SystemExit("gimp failed (exit %d): %s" % (p.returncode, " ".join(cmd)))
    s = gimptest.summary(out)
    pr = s["probes"]["probe"]
    exact = DELTA * pr["x0"][0] / L
    cv = s.get("constraint_violation", {})
    return {
        "name": name, "status": s["status"], "steps": s["steps"], "time": s["time"],
        "wall": s["wall_seconds"], "penalty": s.get("penalty", float("nan")),
        "ux": pr["u"][0], "ux_exact": exact, "ux_err": pr["u"][0] / exact - 1,
        "sxx": pr["stress"][0],
        "r0": s["reactions"]["dbc0"][0] if "reactions" in s else float("nan"),
        "r1": s["reactions"]["dbc1"][0] if "reactions" in s else float("nan"),
        "gap1": cv.get("dbc1", {}).get("final", float("nan")),
        "gap1_max": cv.get("dbc1", {}).get("max", float("nan")),
        "gap0": cv.get("dbc0", {}).get("final", float("nan")),
        "ke": s["energy"]["kinetic"], "se": s["energy"]["strain"], "out": out,
    }


rows = []
dump = os.path.join(a.work, "damped", "particles.csv")
os.makedirs(os.path.dirname(dump), exist_ok=True)
rows.append(run("damped", ["-gimp_history_interval", "10", "-gimp_particle_dump", dump]))
rows.append(run("undamped", ["-gimp_damping", "0", "-gimp_history_interval", "10"]))
for alpha in ALPHAS:
    for trac in ("on", "off"):
        extra = ["-gimp_penalty", repr(alpha)]
        if trac == "off":
            extra += ["-gimp_penalty_traction", "false"]
        r = run("alpha_%g_%s" % (alpha, trac), extra)
        r["alpha"], r["traction"] = alpha, trac
        rows.append(r)

keys = ["name", "status", "alpha", "traction", "penalty", "steps", "wall", "ux", "ux_exact",
        "ux_err", "sxx", "r0", "r1", "gap0", "gap1", "gap1_max", "ke", "se"]
with open(os.path.join(a.work, "slab_runs.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
    w.writeheader()
    for r in rows:
        w.writerow(r)

d = rows[0]
print("Slab, damped (d = 1e6 1/s), %d steps, %.2f s wall; penalty %.4g Pa/m = %.3g M/h_min"
      % (d["steps"], d["wall"], d["penalty"], d["penalty"] * HMIN / M))
print("  probe u_x %.7e m, exact %.7e m, error %.4f %% (paper: 0.46 %%)" %
      (d["ux"], d["ux_exact"], 100 * d["ux_err"]))
print("  final constraint violation: left %.3e m, right %.3e m" % (d["gap0"], d["gap1"]))
print("  kinetic / strain energy at the end: %.2e" % (d["ke"] / d["se"]))

# Stress and reaction against the small-strain and the logarithmic-strain values.
p = gimptest.read_csv(dump)
n = len(p["sxx"])
mean_sxx = sum(p["sxx"]) / n
lnl = math.log(1 + DELTA / L)
s_small, s_log = EP * DELTA / L, EP * lnl
lat_small = -NU / (1 - NU) * DELTA / L          # small-strain lateral strain
stretch_y = math.exp(-NU / (1 - NU) * lnl)       # lateral stretch with the logarithmic strain
ys = p["y"]
span = max(ys) - min(ys)
span0 = H - HMIN / 2                              # first to last particle centre, initially
print("\n| quantity | value |\n| --- | --- |")
print("| E' δ / L (small strain) | %.5e Pa |" % s_small)
print("| E' ln(1 + δ/L) (logarithmic strain) | %.5e Pa (ratio ln(1.05)/0.05 = %.5f) |" %
      (s_log, lnl / (DELTA / L)))
print("| mean σxx over the %d particles | %.5e Pa (%+.2e from E' ln(1.05)) |" %
      (n, mean_sxx, mean_sxx / s_log - 1))
print("| particle σxx, min … max | %+.2e … %+.2e from E' ln(1.05) |" %
      (min(p["sxx"]) / s_log - 1, max(p["sxx"]) / s_log - 1))
print("| probe σxx | %.5e Pa (%+.2e from E' ln(1.05)) |" % (d["sxx"], d["sxx"] / s_log - 1))
print("| lateral strain, small strain −ν/(1−ν) δ/L | %.4f %% |" % (100 * lat_small))
print("| lateral stretch − 1, exp(−ν/(1−ν) ln 1.05) − 1 | %.4f %% |" % (100 * (stretch_y - 1)))
print("| measured (span of the particle centres) | %.4f %% |" % (100 * (span / span0 - 1)))
print("| reaction, right end | %.6e N/m |" % d["r1"])
print("| reaction, left end | %.6e N/m |" % d["r0"])
print("| E' δ H / L (small strain) | %.6e N/m (reaction / this = %.5f) |" %
      (s_small * H, d["r1"] / (s_small * H)))
print("| E' ln(1.05) H exp(−ν/(1−ν) ln 1.05) | %.6e N/m (reaction / this = %.6f) |" %
      (s_log * H * stretch_y, d["r1"] / (s_log * H * stretch_y)))
print("| mean σxx × H × measured lateral stretch | %.6e N/m (reaction / this = %.6f) |" %
      (mean_sxx * H * span / span0, d["r1"] / (mean_sxx * H * span / span0)))

u = rows[1]
print("\nUndamped: status %s; probe u_x at %.0f us: %.5e m" % (u["status"], 1e6 * u["time"], u["ux"]))

print("\n| α [Pa/m] | α h_min / M | traction term | status | violation, right end [m] | "
      "violation, left end [m] | probe u_x error | right reaction [N/m] |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for r in rows[2:]:
    if r["status"] == "refused":
        print("| %.3g | %.3g | %s | refused (input check) | – | – | – | – |" %
              (r["alpha"], r["alpha"] * HMIN / M, r["traction"]))
        continue
    print("| %.3g | %.3g | %s | %s | %.3e | %.3e | %+.4f %% | %.5e |" %
          (r["alpha"], r["alpha"] * HMIN / M, r["traction"], r["status"], r["gap1"], r["gap0"],
           100 * r["ux_err"], r["r1"]))
off = [r for r in rows[2:] if r["traction"] == "off" and r["status"] == "completed"]
print("\nPure penalty: violation × α [N/m²] = " +
      ", ".join("%.4g" % (r["gap1"] * r["alpha"]) for r in off))
print("(σxx at the end, for comparison: %.4g Pa)" % d["sxx"])
print("M = %.5g Pa, M / h_min = %.4g Pa/m, 4 M / h_min = %.4g Pa/m, stable limit 2 ρ h_min / dt² = "
      "%.4g Pa/m" % (M, M / HMIN, 4 * M / HMIN, 2 * RHO * HMIN / DT ** 2))
for r in rows[2:]:
    if r["status"] == "refused":
        print("refused: " + r["message"])
        break
