#!/usr/bin/env python3
"""Every gimp option with values a user might mistype, in 2D and 3D: nothing may crash, hang or
print more than one line, and no numeric option may take a non-number.

For each option of the option table (`gimp -gimp_options_markdown`; indexed options as index 0)
and the PETSc options docs/options.md lists beside it (-log_view, -ts_*, -da_processors_*) and each value of VALUES, runs
the scenes (default options/patch.opts, 2D, and options/patch3d.opts, 3D; --scenes takes others,
e.g. central_crack.opts or a per-level scene) for 4 steps with the option set, two runs at a
time, and reports a run that
- ends by a signal or hangs (60 s),
- fails without exactly one stderr line `gimp: error: ...`,
- succeeds with a value that is not a number (nan, inf, -inf, abc): reported as ACCEPTED, which
  is right only for options whose value is a name (output paths, scene and probe names).
About 20 minutes on two cores (2 scenes x about 135 options x 12 values). The runs' working
directory is --work: a value taken as a file name is written there, never in the repository.

    /usr/bin/python3 tools/fuzz_options.py --gimp build/gimp [--work /tmp/gimp-fuzz]
        [--scenes patch.opts,patch3d.opts,central_crack.opts]
"""
import argparse
import concurrent.futures
import os
import re
import shutil
import subprocess
import tempfile

VALUES = ["nan", "inf", "-inf", "-1", "0", "1e308", "abc", "1,2", "-1e-300", "1e-320", "3.5",
          "1,nan"]
SCENES = ("patch.opts", "patch3d.opts")
# The PETSc options docs/options.md lists beside the table (the table holds gimp's own).
PETSC_OPTIONS = ["-da_processors_x", "-da_processors_y", "-da_processors_z", "-log_view",
                 "-ts_dt", "-ts_exact_final_time", "-ts_max_steps", "-ts_max_time", "-ts_monitor"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gimp", default="build/gimp")
    ap.add_argument("--work", default="/tmp/gimp-fuzz")
    ap.add_argument("--scenes", default=",".join(SCENES),
                    help="comma-separated scene files of options/ (default: %(default)s)")
    a = ap.parse_args()
    scenes = [x for x in a.scenes.split(",") if x]
    gimp = os.path.abspath(a.gimp)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.makedirs(a.work, exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    table = subprocess.run([gimp, "-gimp_options_markdown"], capture_output=True, text=True,
                           env=env).stdout
    # (not the ones that stop before a scene is read: -help, -options_file, the table itself)
    skip = {"-help", "-options_file", "-gimp_options_markdown"}
    options = sorted(set(re.findall(r"^\| `(-[A-Za-z][A-Za-z0-9_]*)`", table, re.M)) - skip)
    options += PETSC_OPTIONS

    def one(job):
        scene, opt, value = job
        opt = opt.replace("K", "0").replace("J", "0")
        out = tempfile.mkdtemp(dir=a.work)
        extra = ["-gimp_bodies", "1"] if "_body0" in opt else []
        cmd = [gimp, "-options_file", os.path.join(root, "options", scene), "-ts_max_steps", "4",
               "-gimp_output_dir", out] + extra + [opt, value]
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env,
                               cwd=a.work)
        except subprocess.TimeoutExpired:
            return scene, opt, value, "HANGS", ""
        finally:
            shutil.rmtree(out, ignore_errors=True)
        err = [l for l in p.stderr.splitlines() if l.strip()]
        bad = None
        if p.returncode < 0 or p.returncode >= 128:
            bad = "SIGNAL (exit %d)" % p.returncode
        elif p.returncode != 0 and (len(err) != 1 or not err[0].startswith("gimp: error:")):
            bad = "NOT ONE LINE (exit %d)" % p.returncode
        elif p.returncode == 0 and value in ("nan", "inf", "-inf", "abc"):
            bad = "ACCEPTED"
        return scene, opt, value, bad, " | ".join(err[:3])[:300]

    jobs = [(s, o, v) for s in scenes for o in options for v in VALUES]
    found = 0
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        for scene, opt, value, bad, err in pool.map(one, jobs):
            if bad:
                found += 1
                print("%-13s %-34s %-8s %s %s" % (scene, opt, value, bad, err), flush=True)
    print("%d runs, %d options, %d reported" % (len(jobs), len(options), found))


if __name__ == "__main__":
    main()
