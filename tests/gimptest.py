"""Shared helpers for the verification scripts: run gimp, read its outputs, assert."""
import argparse
import concurrent.futures
import csv
import math
import json
import os
import shlex
import subprocess
import sys
import threading


def parse_args():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--extra", default="",
                    help="gimp options appended to every run (to see a check fail on a wrong "
                         "input, e.g. --extra '-gimp_nu 0.29')")
    a = ap.parse_args()
    a.gimp, a.root, a.work = (os.path.abspath(p) for p in (a.gimp, a.root, a.work))
    os.makedirs(a.work, exist_ok=True)
    return a


def run(args, opts_file, extra=(), ranks=1, outdir=None, expect_ok=True, cwd=None):
    """Run gimp on opts_file (relative to the repo root) with extra options; return the
    output directory (or the completed process when expect_ok is False). cwd defaults to the
    work directory; a nested -options_file is resolved relative to the including file."""
    outdir = outdir or os.path.join(args.work, os.path.splitext(os.path.basename(opts_file))[0])
    cmd = [args.gimp, "-options_file", os.path.join(args.root, opts_file),
           "-gimp_output_dir", outdir] + list(extra) + shlex.split(getattr(args, "extra", ""))
    if ranks > 1:
        cmd = [args.mpiexec, "-n", str(ranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run(cmd, cwd=cwd or args.work, env=env, capture_output=True, text=True)
    if not expect_ok:
        return p
    if p.returncode != 0:
        sys.stdout.write(p.stdout)
        sys.stderr.write(p.stderr)
        raise SystemExit("gimp failed (exit %d): %s" % (p.returncode, " ".join(cmd)))
    return outdir


def summary(outdir):
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)


def history(outdir):
    """history.csv as a dict of column name -> list of floats."""
    with open(os.path.join(outdir, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def concurrently(calls, workers=2):
    """Run the thunks in calls `workers` at a time (each mostly waits on a gimp process, so
    threads suffice) and return their results in order; the first exception is raised again.
    A test that runs its gimp processes this way claims PROCESSORS 2 in tests/CMakeLists.txt;
    the calls must not share an output directory."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(f) for f in calls]
        return [f.result() for f in futures]


class Checks:
    """Collects named checks, prints each with its measured value, fails at the end."""

    def __init__(self):
        self.failed = []
        self.lock = threading.Lock()

    def check(self, name, ok, detail):
        with self.lock:  # checks made by concurrently()'s threads print whole lines
            sys.stdout.write("%-4s %s: %s\n" % ("ok" if ok else "FAIL", name, detail))
            sys.stdout.flush()
            if not ok:
                self.failed.append(name)

    def done(self):
        if self.failed:
            raise SystemExit("failed: " + ", ".join(self.failed))
        print("all checks passed")


def columns_by_x(d):
    """The particles of a particle dump (read_csv) in columns of one initial x each, in x order:
    a gap along x above the smallest half-size lx starts the next column."""
    order = sorted(range(len(d["x"])), key=lambda i: d["x"][i])
    gap = min(d["lx"])
    cols = [[order[0]]]
    for i in order[1:]:
        if d["x"][i] - d["x"][cols[-1][-1]] > gap:
            cols.append([])
        cols[-1].append(i)
    return cols


def orders(rows, key, hkey="h"):
    """Observed order of rows[key] against rows[hkey] between successive rows (None first), and
    the least-squares slope over all rows."""
    pair = [None] + [math.log(a[key] / b[key]) / math.log(a[hkey] / b[hkey])
                     for a, b in zip(rows, rows[1:])]
    x = [math.log(r[hkey]) for r in rows]
    y = [math.log(r[key]) for r in rows]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    fit = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
    return pair, fit


def fmt_order(p, width=6):
    return "-".rjust(width) if p is None else "%*.2f" % (width, p)
