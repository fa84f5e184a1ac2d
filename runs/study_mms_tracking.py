#!/usr/bin/python3
"""Particle domain tracking on the 1D manufactured solution (options/mms_skb1d.opts).

Runs the scene for -gimp_tracking none, stretch, corners, cpdi and cpdi2 at A = 1e-4 and A = 0.05
(-gimp_mms_amplitude) on h = 1/n (overriding -gimp_h, -gimp_body0_box and -gimp_bc3_y as
tests/check_mms.py does), prints a markdown table of the measured errors (summary.json
measures mms_linf and mms_rms, maxima over one period) with the observed orders between
successive resolutions, and writes them to <work>/mms_tracking.csv.

Usage: /usr/bin/python3 runs/study_mms_tracking.py --gimp build/gimp --work /tmp/mms_tracking
                                                    [--levels 32,64,128]
"""
import argparse
import csv
import json
import math
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ap = argparse.ArgumentParser()
ap.add_argument("--gimp", required=True)
ap.add_argument("--work", required=True)
ap.add_argument("--levels", default="32,64,128")
a = ap.parse_args()
gimp, work = os.path.abspath(a.gimp), os.path.abspath(a.work)
os.makedirs(work, exist_ok=True)
levels = [int(s) for s in a.levels.split(",")]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def run(mode, A, n):
    h = 1.0 / n
    out = os.path.join(work, "%s_A%g_n%d" % (mode, A, n))
    cmd = [gimp, "-options_file", os.path.join(ROOT, "options", "mms_skb1d.opts"),
           "-gimp_output_dir", out, "-gimp_h", repr(h), "-gimp_body0_box", "0,0,1,%r" % h,
           "-gimp_bc3_y", repr(h), "-gimp_tracking", mode, "-gimp_mms_amplitude", repr(A)]
    p = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit("gimp failed (exit %d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr))
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return {"mode": mode, "A": A, "n": n, "status": s["status"],
            "linf": s["measures"]["mms_linf"], "rms": s["measures"]["mms_rms"]}


def order(rows, i, key):
    if i == 0:
        return None
    return math.log(rows[i - 1][key] / rows[i][key]) / math.log(rows[i]["n"] / rows[i - 1]["n"])


def fo(p):
    return "–" if p is None else "%.2f" % p


table = []
for A in (1e-4, 0.05):
    for mode in ("none", "stretch", "corners", "cpdi", "cpdi2"):
        rows = [run(mode, A, n) for n in levels]
        for i, r in enumerate(rows):
            r["order_linf"], r["order_rms"] = order(rows, i, "linf"), order(rows, i, "rms")
        table += rows

print("| A | tracking | h | L-inf [m] | order | RMS [m] | order |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for r in table:
    print("| %g | %s | 1/%d | %.3e | %s | %.3e | %s |" % (r["A"], r["mode"], r["n"], r["linf"],
                                                      fo(r["order_linf"]), r["rms"],
                                                      fo(r["order_rms"])))
path = os.path.join(work, "mms_tracking.csv")
with open(path, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["A", "tracking", "n", "status", "linf", "order_linf", "rms", "order_rms"])
    for r in table:
        w.writerow([repr(r["A"]), r["mode"], r["n"], r["status"], "%.6e" % r["linf"],
                    "" if r["order_linf"] is None else "%.4f" % r["order_linf"],
                    "%.6e" % r["rms"], "" if r["order_rms"] is None else "%.4f" % r["order_rms"]])
print("wrote %s" % path)
