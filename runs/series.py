"""What the speed-against-error studies share: their command line (--gimp, --work, --no-run) and
running gimp on a series of scenes, one output directory each (WORK/run0, run1, ...)."""
import argparse
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def parse_args(work):
    """--gimp (default build/gimp), --work (default build/WORK), --no-run."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", work))
    ap.add_argument("--no-run", action="store_true", help="tables and figure from the last runs")
    a = ap.parse_args()
    a.gimp, a.work = os.path.abspath(a.gimp), os.path.abspath(a.work)  # runs change directory
    return a


def run_series(a, runs, common=(), cwd=None):
    """Runs every (name, scene, extra options, kind) of `runs` with `common` options into
    a.work/run<i> (unless --no-run) and yields (name, kind, output directory, summary.json)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    for i, (name, scene, extra, kind) in enumerate(runs):
        out = os.path.join(a.work, "run%d" % i)
        if not a.no_run:
            subprocess.run([a.gimp, "-options_file", scene, "-gimp_output_dir", out] +
                           list(common) + list(extra), cwd=cwd, env=env, check=True,
                           stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            yield name, kind, out, json.load(f)
