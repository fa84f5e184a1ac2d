#!/usr/bin/python3
"""Critical time step: the prediction of -gimp_stability_check (dt_critical in summary.json)
against the step where runs actually go unstable, found by bisection. The table of
docs/validation.md, section "Critical time step".

Usage: /usr/bin/python3 runs/study_stability.py --gimp build/gimp --work build/WORK_stability
       [--root .] [--steps 1500] [--cases bar,patch3,...] [--transfer flip|apic]
(gimp built with SLEPc.)

Each case runs undamped (unless it is the damped case) for a fixed number of steps with
-gimp_allow_unstable_dt. A run is unstable when it stops with status "unstable" (a particle
not finite or out of the grid) or its energy (kinetic + strain) at the end exceeds 100 times
its largest value over the first half of the run. Without damping the growth of a mode above
its bound is |z| > 1 per step from round-off, so a few hundred steps make it visible within a
fraction of a percent of the threshold. Bisection on dt / dt_critical between a stable and
an unstable factor, to a bracket of 0.5 %; the measured threshold is the bracket's middle.
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import series  # noqa: E402

SLAB = ["-gimp_damping", "0"]
CASES = [
    ("bar", "bar.opts", ["-ts_max_time", "1e9"]),
    ("patch3", "patch3.opts", ["-gimp_damping", "0"]),
    ("slab a=2e15 traction", "slab.opts", SLAB + ["-gimp_penalty", "2e15"]),
    ("slab a=1e16 traction", "slab.opts", SLAB + ["-gimp_penalty", "1e16"]),
    ("slab a=1e17 traction", "slab.opts", SLAB + ["-gimp_penalty", "1e17"]),
    ("slab a=2e15 springs", "slab.opts",
     SLAB + ["-gimp_penalty", "2e15", "-gimp_penalty_traction", "false"]),
    ("slab a=1e16 springs", "slab.opts",
     SLAB + ["-gimp_penalty", "1e16", "-gimp_penalty_traction", "false"]),
    ("slab a=1e17 springs", "slab.opts",
     SLAB + ["-gimp_penalty", "1e17", "-gimp_penalty_traction", "false"]),
    ("plate ring (25 ppc)", "plate.opts", ["-gimp_damping", "0", "-gimp_flip", "1"]),
    ("bar damped d=10", "bar.opts", ["-ts_max_time", "1e9", "-gimp_damping", "10"]),
    ("bar damped d=30", "bar.opts", ["-ts_max_time", "1e9", "-gimp_damping", "30"]),
    ("bar USL", "bar.opts", ["-ts_max_time", "1e9", "-gimp_update", "usl"]),
    ("bar USF", "bar.opts", ["-ts_max_time", "1e9", "-gimp_update", "usf"]),
]


def run(a, scene, extra, out, dt=None):
    """One run; returns its summary and whether it went unstable."""
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = [a.gimp, "-options_file", os.path.join(a.root, "options", scene),
           "-gimp_output_dir", out, "-gimp_stability_check", "-gimp_allow_unstable_dt",
           "-gimp_transfer", a.transfer,
           "-ts_max_steps", str(a.steps), "-gimp_history_interval", "10",
           "-gimp_output_interval", "0"] + extra
    if dt is not None:
        cmd += ["-ts_dt", "%.9e" % dt]
    p = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if p.returncode not in (0, 3):
        sys.exit("gimp failed (exit %d): %s" % (p.returncode, " ".join(cmd)))
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    if s["status"] == "unstable":
        return s, True
    with open(os.path.join(out, "history.csv")) as f:
        rows = [line.split(",") for line in f.read().split("\n")[1:] if line]
    e = [float(r[2]) + float(r[3]) for r in rows]
    early = max(e[: max(1, len(e) // 2)])
    return s, not (e[-1] <= 100.0 * max(early, 1e-300))


def threshold(a, name, scene, extra, dtc):
    """Bisection on the factor f = dt / dt_critical."""
    out = os.path.join(a.work, name.replace(" ", "_").replace("=", ""))
    lo, hi = 0.8, 1.25
    while run(a, scene, extra, out, lo * dtc)[1]:
        lo *= 0.8
    while not run(a, scene, extra, out, hi * dtc)[1]:
        lo, hi = hi, hi * 1.25
        if hi > 8:
            return lo, float("inf")
    while hi - lo > 0.005:
        mid = 0.5 * (lo + hi)
        if run(a, scene, extra, out, mid * dtc)[1]:
            hi = mid
        else:
            lo = mid
    return lo, hi


def main():
    ap = series.argparse.ArgumentParser()
    ap.add_argument("--gimp", default=os.path.join(series.ROOT, "build", "gimp"))
    ap.add_argument("--root", default=series.ROOT, help="the repository (its options/)")
    ap.add_argument("--work", default=os.path.join(series.ROOT, "build", "WORK_stability"))
    ap.add_argument("--steps", type=int, default=1500)
    ap.add_argument("--cases", default="", help="comma-separated prefixes of the case names")
    ap.add_argument("--transfer", default="flip", choices=("flip", "apic"),
                    help="-gimp_transfer of every run (the plate ring blends FLIP: flip only)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    wanted = [c for c in a.cases.split(",") if c]
    print("| case | dt_critical predicted [s] | measured threshold [s] | measured / predicted |")
    print("| --- | --- | --- | --- |")
    worst = 0.0
    for name, scene, extra in CASES:
        if wanted and not any(name.startswith(w) for w in wanted):
            continue
        s, _ = run(a, scene, extra + ["-ts_max_steps", "1"], os.path.join(a.work, "predict"))
        dtc = s["dt_critical"]
        lo, hi = threshold(a, name, scene, extra, dtc)
        ratio = 0.5 * (lo + hi)
        worst = max(worst, abs(ratio - 1.0))
        print("| %s | %.4e | %.4e (%.3f to %.3f) | %.3f |" %
              (name, dtc, ratio * dtc, lo, hi, ratio), flush=True)
    print("\nlargest |measured / predicted - 1| = %.1f %%" % (100 * worst))


if __name__ == "__main__":
    main()
