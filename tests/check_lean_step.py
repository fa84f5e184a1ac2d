"""gimp's default step against an independent implementation of it (bench/lean_step.cpp).

bench/lean_step is a 250-line step written for the benchmark block alone: one uniform level,
GIMP weights on 3 x 3 blocks, APIC with MUSL, the Jaumann rate in plane strain, stretch
tracking. It shares no code with gimp. Both run bench/block.opts at h = 1/32 (4096 particles)
for 50 steps; every particle, matched by its initial position, must agree in position,
velocity, APIC's B, the four stresses, volume and domain half-sizes to TOL of the column's
largest magnitude. Measured agreement is 2e-11 or better (round-off of the two summation
orders, grown over 50 steps); a change of the physics shows at 1e-5 or more: --extra
'-gimp_nu 0.30001' gives 1e-5 to 1e-4 in v, B and the stress, '-gimp_tracking none' 2e-3 in
l, '-gimp_update usl' 1e-2 in v (and '-gimp_transfer flip' writes no B).

Extra options (besides those of gimptest.parse_args):
  --lean PATH    the lean_step executable (build/bench/lean_step)
"""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

import gimptest

TOL = 1e-9
CELLS, STEPS = 32, 50
COLUMNS = "X0_x X0_y x_x x_y v_x v_y B_xx B_xy B_yx B_yy s_xx s_xy s_yy s_zz V l_x l_y".split()

pre = argparse.ArgumentParser(add_help=False)
pre.add_argument("--lean", required=True)
mine, rest = pre.parse_known_args()
sys.argv = sys.argv[:1] + rest
args = gimptest.parse_args()
checks = gimptest.Checks()

lean_out = os.path.join(args.work, "lean.txt")
p = subprocess.run([mine.lean, "-cells", str(CELLS), "-steps", str(STEPS), "-out", lean_out],
                   capture_output=True, text=True)
sys.stdout.write(p.stdout)
if p.returncode != 0:
    sys.stderr.write(p.stderr)
    raise SystemExit("lean_step failed (exit %d)" % p.returncode)
lean = np.loadtxt(lean_out)

out = gimptest.run(args, "bench/block.opts",
                   extra=["-gimp_h", repr(1.0 / CELLS), "-ts_max_steps", str(STEPS)],
                   outdir=os.path.join(args.work, "block"))
with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
    g = f["particles/step_%08d" % STEPS]
    wanted = ("X0", "x", "v", "B", "stress", "szz", "V", "l")
    missing = [k for k in wanted if k not in g]
    checks.check("fields written", not missing, "missing: %s" % (missing or "none"))
    if missing:
        checks.done()
    s = g["stress"][:]
    mine_cols = np.column_stack([g["X0"][:], g["x"][:], g["v"][:], g["B"][:], s[:, 0], s[:, 1],
                                 s[:, 3], g["szz"][:], g["V"][:], g["l"][:]])


def by_position(a):
    """Rows ordered by initial position (y, then x), on a lattice of 1e-9 m."""
    return a[np.lexsort((np.round(a[:, 0] * 1e9), np.round(a[:, 1] * 1e9)))]


lean, mine_cols = by_position(lean), by_position(mine_cols)
checks.check("particle count", lean.shape == mine_cols.shape,
             "lean %s, gimp %s" % (lean.shape, mine_cols.shape))
if lean.shape == mine_cols.shape:
    same_seed = np.array_equal(lean[:, :2], mine_cols[:, :2])
    checks.check("same initial positions", same_seed, "X0 of every particle")
    for i, name in enumerate(COLUMNS[2:], start=2):
        scale = np.abs(lean[:, i]).max()
        diff = np.abs(lean[:, i] - mine_cols[:, i])
        worst = int(diff.argmax())
        rel = diff[worst] / scale if scale > 0 else diff[worst]
        checks.check(name, bool(np.all(np.isfinite(mine_cols[:, i]))) and rel <= TOL,
                     "largest difference %.2e of the column's scale %.3e (particle at X0 = "
                     "(%.5f, %.5f)), tolerance %.0e" % (rel, scale, lean[worst, 0],
                                                        lean[worst, 1], TOL))
checks.done()
