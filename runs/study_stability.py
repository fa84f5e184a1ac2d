"""Critical time step: the eigenvalue estimate against the step where runs go unstable.

For each case the predicted dt_critical is read from summary.json of a one-step run with
-gimp_stability_check; then the time step at which the run actually goes unstable is found by
bisection on -ts_dt (with -gimp_allow_unstable_dt). A run counts as unstable when it stops with
status "unstable" or when its energy (kinetic + strain) at the end exceeds GROWTH times its largest
value over the first half of the run. Near the threshold the highest mode grows by about
1 + 2 sqrt(2 e) per step at dt = (1 + e) dt_critical, so from round-off (1e-16) it reaches any
visible size within a few hundred steps for e >= 1e-3: a few thousand steps without damping
resolve the threshold to well under 1 %.

    python3 runs/study_stability.py --gimp build/gimp [--work build/stability] [--only bar,slab]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GROWTH = 100.0

# name, options file, extra options, steps. Undamped unless the case says otherwise; coarse and
# short so that the whole study takes minutes.
UNDAMPED = ["-gimp_damping", "0"]
CASES = [
    ("bar (1 level, MUSL)", "options/bar.opts", [], 2000),
    ("bar, USL", "options/bar.opts", ["-gimp_update", "usl"], 2000),
    ("bar, USF", "options/bar.opts", ["-gimp_update", "usf"], 2000),
    ("bar, PIC (flip 0)", "options/bar.opts", ["-gimp_flip", "0"], 2000),
    ("patch, 3 levels", "options/patch3.opts", UNDAMPED, 2000),
]
for alpha_rel in (10, 100, 1000):
    for trac in ("false", "true"):
        CASES.append(("slab, alpha %g M/h, traction %s" % (alpha_rel, trac), "options/slab.opts",
                      UNDAMPED + ["-gimp_penalty_rel", str(alpha_rel),
                                  "-gimp_penalty_traction", trac], 2000))
CASES += [
    ("plate, 25-particle ring", "options/plate.opts",
     UNDAMPED + ["-gimp_body0_box", "0,0,0.008,0.008", "-gimp_traction0_value", "1e8,0"], 2000),
    ("bar, damped d = 10 1/s", "options/bar.opts", ["-gimp_damping", "10"], 2000),
]


def gimp_run(a, scene, extra, out):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = [a.gimp, "-options_file", os.path.join(ROOT, scene), "-gimp_output_dir", out,
           "-gimp_stability_check", "-gimp_allow_unstable_dt", "-gimp_output_interval", "0"]
    p = subprocess.run(cmd + extra, env=env, capture_output=True, text=True)
    if p.returncode not in (0, 3):
        sys.exit("gimp failed (%d): %s\n%s" % (p.returncode, " ".join(cmd + extra), p.stderr))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def energies(out):
    with open(os.path.join(out, "history.csv")) as f:
        return [float(r["kinetic"]) + float(r["strain"]) for r in csv.DictReader(f)]


def unstable(a, scene, extra, steps, dt, out):
    s = gimp_run(a, scene, extra + ["-ts_dt", repr(dt), "-ts_max_steps", str(steps),
                                    "-ts_max_time", "1e300",
                                    "-gimp_history_interval", str(max(1, steps // 100))], out)
    if s["status"] == "unstable":
        return True
    e = energies(out)
    first = max(e[: len(e) // 2]) if len(e) > 1 else e[0]
    return not math.isfinite(e[-1]) or e[-1] > GROWTH * max(first, 1e-300)


def measure(a, name, scene, extra, steps, work):
    out = os.path.join(work, "run")
    # The penalty relative to M / h_min: read the scene's M and h from the first run.
    extra = list(extra)
    if "-gimp_penalty_rel" in extra:
        i = extra.index("-gimp_penalty_rel")
        rel = float(extra[i + 1])
        del extra[i:i + 2]
        extra += ["-gimp_penalty", repr(rel * penalty_unit(a, scene, extra, out))]
    s = gimp_run(a, scene, extra + ["-ts_max_steps", "1"], out)
    pred = s["dt_critical"]
    lo, hi = 0.5, 1.0
    while unstable(a, scene, extra, steps, hi * pred, out):  # stable end below the threshold
        hi, lo = lo, lo / 2
        if hi < 0.05:
            return pred, float("nan"), "unstable at every dt"
    lo = hi
    hi = lo * 1.05
    while not unstable(a, scene, extra, steps, hi * pred, out):
        lo, hi = hi, hi * 1.25
        if hi > 8:
            return pred, float("nan"), "stable up to 8 dt_critical"
    while hi / lo > 1.0025:
        mid = math.sqrt(lo * hi)
        if unstable(a, scene, extra, steps, mid * pred, out):
            hi = mid
        else:
            lo = mid
    return pred, math.sqrt(lo * hi) * pred, ""


def penalty_unit(a, scene, extra, out):
    """M / h_min of the scene [Pa/m], from gimp's penalty line (alpha and alpha h / M)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = [a.gimp, "-options_file", os.path.join(ROOT, scene), "-gimp_output_dir", out,
           "-ts_max_steps", "0", "-gimp_penalty_traction", "false"] + \
        [x for x in extra if x != "-gimp_penalty_traction"]
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    for line in p.stdout.splitlines():
        if line.startswith("gimp: penalty alpha = "):
            words = line.split()
            return float(words[4]) / float(words[6].lstrip("("))
    sys.exit("no penalty line from: " + " ".join(cmd) + "\n" + p.stdout + p.stderr)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "stability"))
    ap.add_argument("--only", default="", help="comma-separated words: cases whose name has one")
    a = ap.parse_args()
    words = [w for w in a.only.split(",") if w]
    print("| case | steps | predicted dt_critical [s] | measured threshold [s] | measured / "
          "predicted |")
    print("| --- | --- | --- | --- | --- |")
    for i, (name, scene, extra, steps) in enumerate(CASES):
        if words and not any(w in name for w in words):
            continue
        work = os.path.join(a.work, "case%d" % i)
        os.makedirs(work, exist_ok=True)
        t0 = time.time()
        pred, meas, note = measure(a, name, scene, extra, steps, work)
        ratio = meas / pred
        print("| %s | %d | %.4e | %.4e | %.3f%s |" % (name, steps, pred, meas, ratio,
                                                       " (" + note + ")" if note else ""),
              flush=True)
        print("  (%.0f s)" % (time.time() - t0), file=sys.stderr, flush=True)


if __name__ == "__main__":
    main()
