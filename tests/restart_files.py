"""Shared by check_restart.py and check_restart3d.py: the outputs a restart must reproduce bit for
bit (the last frame of fields.h5, history.csv, the particle dump, summary.json but its timing
keys, and particles.xmf when the restart continued in its checkpoint's directory)."""
import os

import h5py
import numpy as np

import gimptest

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
TIMING = ("wall_seconds", "setup_seconds", "cpu_seconds", "particle_steps_per_second")


def run_with_dump(args, scene, name, extra=(), ranks=1, expect_ok=True):
    """Run scene = (options file, options) into args.work/name with a particle dump there."""
    d = os.path.join(args.work, name)
    opts, base = scene
    os.makedirs(d, exist_ok=True)
    return gimptest.run(args, opts, base + ["-gimp_particle_dump", os.path.join(d, "particles.csv")]
                        + list(extra), ranks=ranks, outdir=d, expect_ok=expect_ok)


def last_frame(d):
    """(name, {field: array}) of the last particle frame in d/fields.h5."""
    with h5py.File(os.path.join(d, "fields.h5"), "r") as f:
        g = sorted(f["particles"].keys())[-1]
        return g, {k: np.array(f["particles"][g][k]) for k in f["particles"][g]}


def summary_minus_timing(d):
    return {k: v for k, v in gimptest.summary(d).items() if k not in TIMING}


def same_bits(c, name, ref, got, same_dir=True):
    """Check (on gimptest.Checks c) that run directory got reproduces ref bit for bit."""
    gr, fr = last_frame(ref)
    gg, fg = last_frame(got)
    fields = gr == gg and fr.keys() == fg.keys() and all(
        fr[k].shape == fg[k].shape and np.array_equal(fr[k].view(np.uint64), fg[k].view(np.uint64))
        for k in fr)
    # A fresh directory has no frames before the checkpoint: its XDMF lists the later ones.
    names = ("history.csv", "particles.csv") + (("particles.xmf",) if same_dir else ())
    files = {f: open(os.path.join(ref, f), "rb").read() == open(os.path.join(got, f), "rb").read()
             for f in names}
    summ = summary_minus_timing(ref) == summary_minus_timing(got)
    c.check(name, fields and all(files.values()) and summ,
            "last frame %s vs %s (%d fields) %s, %s, summary %s" % (
                gr, gg, len(fr), "identical" if fields else "DIFFER",
                ", ".join("%s %s" % (f, "same" if ok else "DIFFERS") for f, ok in files.items()),
                "same" if summ else "DIFFERS"))
