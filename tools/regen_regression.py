#!/usr/bin/env python3
"""Rewrite the regression tier's references (tests/regression/<name>.<ranks>.json) from a gimp
binary, after a change of answers that is meant; `git diff tests/regression` then shows what
changed. Every scene and variant on 1 and 2 ranks unless narrowed:

    tools/regen_regression.py [--gimp build/gimp] [--scene NAME ...] [--ranks 1 2] [--steps N]

A reference keeps the steps it was made with (so regenerating runs the same steps again);
--steps N changes them for the scenes named. A new scene (options/ or bench/) takes the steps
of tests/check_regression.py's STEPS (default DEFAULT_STEPS). Check afterwards with
    python3 tests/check_regression.py --gimp build/gimp       (or: cd build && ctest -L regression)
"""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
import check_regression  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gimp", default=os.path.join(ROOT, "build", "gimp"))
    ap.add_argument("--scene", nargs="+", metavar="NAME")
    ap.add_argument("--ranks", nargs="+", default=["1", "2"])
    ap.add_argument("--steps")
    ap.add_argument("--work", default="/tmp/gimp-regression-regen")
    ap.add_argument("--mpiexec", default="mpiexec")
    a = ap.parse_args()
    argv = ["--regen", "--gimp", a.gimp, "--work", a.work, "--mpiexec", a.mpiexec,
            "--ranks"] + a.ranks
    if a.scene:
        argv += ["--scene"] + a.scene
    if a.steps:
        argv += ["--steps", a.steps]
    return check_regression.main(argv)


if __name__ == "__main__":
    sys.exit(main())
