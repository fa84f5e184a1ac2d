"""The kernels in lanes (-gimp_lanes: 2D four particles at a time, transfer/lane_loops.hpp; 3D a
node's three components at once, transfer/lane_loops3.hpp) against the scalar kernels: every scene
kind must give the same bits.

Each case runs twice, with -gimp_lanes true and false, and compares the last frame of
fields.h5 (every particle field, every particle) and every column of history.csv for exact
equality. The cases cover what decides which particles run in lanes and how their sums are
ordered: one level with APIC (every kernel in lanes), USL and USF (APIC's G2P without the
re-projection), three levels (block particles next to
rows at level borders), the plate with a hole (cut particles, tractions, penalty conditions),
a crack (cracked nodes keep rows), FLIP (force and gradient in lanes, transfers scalar), corner
tracking (stencil centres other than the positions), two ranks, a step per level (each rate
class's stencils), and for the stress update two
materials, a neo-Hookean one (scalar) and plane stress without domain tracking.

When the processor has no AVX2 the lanes do not run and the comparison is trivial; the script
says so (gimp -info reports which kernels ran).
"""
import os
import sys

import h5py
import numpy as np

import gimptest

args = gimptest.parse_args()
checks = gimptest.Checks()

CASES = [
    ("block_apic", "bench/block.opts", ["-gimp_h", "0.03125", "-ts_max_steps", "60"], 1),
    ("block3", "bench/block3.opts", ["-ts_max_steps", "20"], 1),
    ("plate", "options/plate.opts", ["-ts_max_steps", "40"], 1),
    ("dcb", "options/dcb.opts", ["-ts_max_steps", "40"], 1),
    # USL and USF: APIC's G2P without its re-projection
    ("block_usl", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_update", "usl"], 1),
    ("indentation_usf", "options/indentation_a.opts", ["-ts_max_steps", "40", "-gimp_update", "usf"],
     1),
    ("block_flip", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_transfer", "flip"], 1),
    ("patch_corners", "options/patch.opts", ["-ts_max_steps", "60", "-gimp_tracking", "corners"],
     1),
    ("block3_2ranks", "bench/block3.opts", ["-ts_max_steps", "20"], 2),
    # a step per level: each rate class's stencils have lane groups of their own
    ("block3_multirate", "bench/block3_tenth.opts",
     ["-gimp_h", "0.03125", "-gimp_level1_box", "0.375,0.375,0.625,0.625", "-gimp_level2_box",
      "0.4375,0.4375,0.5625,0.5625", "-gimp_multirate", "true", "-ts_max_steps", "32"], 1),
    ("bimaterial", "options/bimaterial.opts", ["-ts_max_steps", "60"], 1),
    ("block_neohookean", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_material", "neohookean"], 1),
    ("block_no_tracking", "bench/block.opts",
     ["-gimp_h", "0.03125", "-ts_max_steps", "60", "-gimp_tracking", "none", "-gimp_plane",
      "stress"], 1),
    # 3D: a node's three components in lanes (APIC and FLIP, with the re-projection and without,
    # one level and three, a step per level, two ranks); the stress update in lanes of four
    ("block3d_apic", "bench/block3d.opts", ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30"],
     1),
    ("block3d_flip_usl", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_transfer", "flip",
      "-gimp_update", "usl"], 1),
    ("block3d_levels_flip", "bench/block3d_levels.opts",
     ["-ts_max_steps", "12", "-gimp_transfer", "flip"], 1),
    ("block3d_levels_usf", "bench/block3d_levels.opts", ["-ts_max_steps", "12", "-gimp_update", "usf"],
     1),
    ("block3d_multirate", "bench/block3d_levels.opts",
     ["-ts_max_steps", "12", "-gimp_transfer", "flip", "-gimp_multirate", "true"], 1),
    ("block3d_2ranks", "bench/block3d_levels.opts", ["-ts_max_steps", "12"], 2),
    # the 3D stress update four particles at a time: linear (stretch, none), neo-Hookean (scalar)
    ("block3d_no_tracking", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_tracking", "none"], 1),
    ("block3d_two_materials", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_bodies", "2", "-gimp_body0_box",
      "0,0,0,0.4583333333333333,1,1", "-gimp_body1_box", "0.4583333333333333,0,0,1,1,1",
      "-gimp_body1_ppc", "8", "-gimp_body1_E", "2e9", "-gimp_body1_velocity", "1,1,1",
      "-gimp_body1_velocity_profile", "sine_x", "-gimp_body1_wavenumber", "6.283185307179586"], 1),
    ("block3d_neohookean", "bench/block3d.opts",
     ["-gimp_h", "0.0833333333333333", "-ts_max_steps", "30", "-gimp_material", "neohookean"], 1),
]


def last_frame(outdir):
    with h5py.File(os.path.join(outdir, "fields.h5"), "r") as f:
        steps = sorted(f["particles"].keys())
        g = f["particles"][steps[-1]]
        return steps[-1], {k: g[k][:] for k in g}


used = None
for name, opts, extra, ranks in CASES:
    runs = {}
    for lanes in ("true", "false"):
        out = os.path.join(args.work, "%s_%s" % (name, lanes))
        p = gimptest.run(args, opts, extra=extra + ["-gimp_lanes", lanes, "-gimp_history_interval", "5", "-info", ":sys"],
                         ranks=ranks, outdir=out, expect_ok=False)
        if p.returncode != 0:
            sys.stdout.write(p.stdout[-2000:])
            sys.stderr.write(p.stderr[-2000:])
            raise SystemExit("gimp failed on %s (-gimp_lanes %s)" % (name, lanes))
        if lanes == "true" and used is None:
            used = "in lanes: yes" in p.stdout + p.stderr or \
                "lanes of four particles: yes" in p.stdout + p.stderr
        runs[lanes] = out
    step_a, a = last_frame(runs["true"])
    step_b, b = last_frame(runs["false"])
    differing = [k for k in a if k not in b or not np.array_equal(a[k], b[k], equal_nan=True)]
    checks.check("%s: particles" % name, step_a == step_b and not differing and len(a) == len(b),
                 "frame %s, %d fields, %s" % (step_a, len(a),
                                              "differ: %s" % differing if differing else
                                              "all bit for bit"))
    ha, hb = gimptest.history(runs["true"]), gimptest.history(runs["false"])
    cols = [k for k in ha if k not in ("wall_seconds", "cpu_seconds") and ha[k] != hb.get(k)]
    checks.check("%s: history" % name, not cols,
                 "%d rows, %s" % (len(ha["step"]), "differ: %s" % cols if cols else "identical"))
print("lanes ran: %s" % ("yes" if used else "no (no AVX2 here: the comparison is trivial)"))
checks.done()
