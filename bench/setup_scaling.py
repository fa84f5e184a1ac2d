#!/usr/bin/env python3
"""Setup cost and memory against the particle count in 3D (docs/performance.md, *Large runs*).

Runs bench/block3d_levels.opts (a cube on three levels, ratios 2 and 2, the finest box an
eighth of the cube's side... 36 % of the particles) with its level-0 cell h0 divided by s, so
that the particle count grows as s^3 (s = 1: 90,112 particles; s = 4: 5.77 million), for a
few steps each, and prints per run:
  - particles, the setup's wall time (summary.json setup_seconds: reading the scene to the
    first step: grid, seeding, checks, stencils' first sizes, TS, outputs opened) and the
    -log_view Setup stage;
  - the stepping time per step (the stages P2G, Forces, Grid update, G2P, Stress over the
    steps run) and the setup's share of a 1000-step run, setup / (setup + 1000 step);
  - the peak resident memory (getrusage of the child) and bytes per particle (peak memory
    minus that of a run with the same grid and a body of one cell, per particle).
Then the exponent b of setup time ~ N^b fitted by least squares in log-log over the runs.

    /usr/bin/python3 bench/setup_scaling.py [--gimp build/gimp] [--scales 1 2 3 4] [--steps 5]

One run at a time, on one rank. The machine line (bench/machine.sh) is printed first.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
H0 = 0.0625  # bench/block3d_levels.opts


def run(gimp, work, s, steps, tiny=False):
    """One run of the scene with h0 / s; returns (summary, Setup stage seconds, stepping seconds,
    peak RSS in bytes)."""
    out = os.path.join(work, "s%g%s" % (s, "_tiny" if tiny else ""))
    cmd = [gimp, "-options_file", os.path.join(ROOT, "bench", "block3d_levels.opts"),
           "-gimp_h", repr(H0 / s), "-ts_max_steps", str(steps), "-gimp_output_dir", out,
           "-log_view", "ascii:" + os.path.join(work, "log_s%g%s.txt" % (s, "_tiny" if tiny else ""))]
    h, lo, hi = H0 / s, -2 * H0 / s, 1 + 2 * H0 / s  # the scene's own domain: 2 cells of pad
    cmd += ["-gimp_domain", ",".join(repr(v) for v in (lo, lo, lo, hi, hi, hi))]
    if tiny:  # one cell of level 0 in a corner: the grid's memory without the particles
        cmd += ["-gimp_body0_box", "0,0,0,%r,%r,%r" % (h, h, h)]
    errfile = os.path.join(work, "err_s%g%s.txt" % (s, "_tiny" if tiny else ""))
    with open(errfile, "w") as err:
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        _, status, use = os.wait4(p.pid, 0)  # this child's own peak resident memory
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        with open(errfile) as f:
            sys.exit("gimp failed on s = %g: %s" % (s, f.read().strip()))
    rss = use.ru_maxrss * 1024  # KiB on Linux
    with open(os.path.join(out, "summary.json")) as f:
        summ = json.load(f)
    stages = {}
    with open(os.path.join(work, "log_s%g%s.txt" % (s, "_tiny" if tiny else ""))) as f:
        for line in f:
            m = re.match(r"^\s*\d+:\s+([A-Za-z0-9 ]+?):\s+([0-9.eE+-]+)", line)
            if m:
                stages[m.group(1)] = float(m.group(2))
    stepping = sum(stages.get(k, 0.0) for k in ("P2G", "Forces", "Grid update", "G2P", "Stress"))
    return summ, stages.get("Setup", float("nan")), stepping, rss


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
    ap.add_argument("--work", default="/tmp/gimp-setup-scaling")
    ap.add_argument("--scales", nargs="+", type=float, default=[1, 1.5, 2, 2.5, 3, 4])
    ap.add_argument("--steps", type=int, default=5)
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    subprocess.run(["bash", os.path.join(ROOT, "bench", "machine.sh")])
    print("%5s %10s %9s %9s %10s %12s %11s %9s" % ("s", "particles", "setup_s", "Setup_st",
          "step_s", "setup/1000", "peak_MB", "B/part"))
    rows = []
    for s in sorted(a.scales):
        _, _, _, rss0 = run(a.gimp, a.work, s, 1, tiny=True)
        summ, st, stepping, rss = run(a.gimp, a.work, s, a.steps)
        n = summ["particles"]
        per_step = stepping / max(summ["steps"], 1)
        share = summ["setup_seconds"] / (summ["setup_seconds"] + 1000 * per_step)
        bpp = (rss - rss0) / n if rss > rss0 else float("nan")
        rows.append((n, summ["setup_seconds"]))
        print("%5g %10d %9.2f %9.2f %10.4f %11.1f%% %11.0f %9.0f" %
              (s, n, summ["setup_seconds"], st, per_step, 100 * share, rss / 2**20, bpp))
    if len(rows) >= 2:
        xs = [math.log(n) for n, _ in rows]
        ys = [math.log(t) for _, t in rows]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        print("setup time ~ N^%.2f (least squares in log-log over %d runs, %d to %d particles)" %
              (b, len(rows), rows[0][0], rows[-1][0]))
    print("setup_s: summary.json setup_seconds; Setup_st: the -log_view Setup stage; step_s: the "
          "stepping stages per step; setup/1000: setup / (setup + 1000 steps); B/part: peak RSS "
          "minus a one-cell body's on the same grid, per particle")


if __name__ == "__main__":
    main()
