"""Particles ordered by cell in 3D (-gimp_sort_interval; docs/options.md), as tests/check_sort.py
does in 2D. Every -gimp_sort_interval steps (at the start of the step) each rank orders its
particles by level-0 cell (x fastest, then y, then z) and by id within a cell; only the order of
the sums changes.

Scene: the 3D block on two levels thrown across the rank boundary and stretched
(options/migrate3d.opts, 301 steps, frames at steps 300 and 301), with sort intervals 0, 1 and 50
(the default; 300 is a multiple), on 1 and 2 ranks. Checked (measured in brackets):
- frame 301 lists the particles in the order of the sort at the start of the step between the
  two frames: by (level-0 cell, id) of their positions at step 300 (ids from the step-0 dump,
  matched by X0), each rank's in order (on 2 ranks the frame is rank 0's then rank 1's, so at
  most one descent) [0 descents on 1 rank, 1 on 2]; without sorting the particles have left that
  order as they moved [1 rank: 100 descents, 2 ranks: 206] (so that the check means something);
- the particles after 301 steps with sort interval 1 and 50 equal those without sorting within
  1e-12 of each quantity's group, and every history column [9.4e-14, 2e-13]; on 2 ranks (with
  migration, 261 particles) likewise against 1 rank unsorted [9.7e-14].
"""
import math
import os

import h5py

import compare3d
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
OPTS = "options/migrate3d.opts"


def cell_id_keys(out, ids_by_x0, before, after):
    """(level-0 cell, id) of every particle at frame `before`, in the order of frame `after`."""
    lv = gimptest.summary(out)["levels"][0]
    box, h = lv["box"], lv["h"]
    n = lv["nodes"]
    with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
        xb, Xb = f["particles/%s/x" % before][()], f["particles/%s/X0" % before][()]
        Xa = f["particles/%s/X0" % after][()]
    at = {tuple(X): x for X, x in zip(Xb, xb)}
    keys = []
    for X in Xa:
        x = at[tuple(X)]
        i, j, k = (int(math.floor((x[a] - box[a]) / h)) for a in range(3))
        keys.append(((k * n[1] + j) * n[0] + i, ids_by_x0[tuple(X)]))
    return keys


def descents(keys):
    return sum(a > b for a, b in zip(keys, keys[1:]))


_, dump0 = compare3d.dump_run(args, OPTS, "step0", ["-ts_max_steps", "0"])
d0 = compare3d.read_dump(dump0)[1]
ids_by_x0 = {(x, y, z): i for i, x, y, z in zip(d0["id"], d0["x"], d0["y"], d0["z"])}

# Frames at steps 300 and 301: a sort (interval 1, or 50 of which 300 is a multiple) at the start
# of the step between them.
STEPS = ["-ts_max_steps", "301", "-gimp_output_interval", "300"]
runs = {}
for ranks, interval in ((1, 0), (1, 1), (1, 50), (2, 0), (2, 1), (2, 50)):
    out, dump = compare3d.dump_run(args, OPTS, "sort%d_np%d" % (interval, ranks),
                                   STEPS + ["-gimp_sort_interval", str(interval)], ranks=ranks)
    keys = cell_id_keys(out, ids_by_x0, "step_00000300", "step_00000301")
    runs[(ranks, interval)] = (out, compare3d.read_dump(dump)[1], gimptest.history(out),
                               descents(keys), len(keys))

# A frame lists rank 0's particles, then rank 1's: each rank's in order leaves at most one
# descent where they meet.
for ranks, interval in sorted(runs):
    n_desc, n = runs[(ranks, interval)][3:]
    if interval == 0:
        c.check("unsorted particles leave cell order, %d rank(s)" % ranks, n_desc > ranks - 1,
                "%d particles in frame 301 listed against their (cell, id) at step 300: %d "
                "descents (more than %d: not in order, as it must be for the next checks to "
                "mean something)" % (n, n_desc, ranks - 1))
    else:
        c.check("ordered by cell after the sort, interval %d, %d rank(s)" % (interval, ranks),
                n_desc <= ranks - 1,
                "%d particles in frame 301 listed against their (cell, id) at step 300: %d "
                "descents (at most %d: each rank's particles in order)" %
                (n, n_desc, ranks - 1))

ref = runs[(1, 0)]
for ranks, interval in ((1, 1), (1, 50), (2, 0), (2, 1), (2, 50)):
    out, d, h = runs[(ranks, interval)][:3]
    dd, group = compare3d.dump_diff(ref[1], d)
    hd, col = compare3d.history_diff(ref[2], h)
    mig = gimptest.summary(out)["measures"]["particles_migrated"]
    c.check("sort interval %d, %d rank(s) = unsorted, 1 rank" % (interval, ranks),
            dd < 1e-12 and hd < 1e-12 and (ranks == 1 or mig > 0),
            "%d particles after 301 steps: largest difference %.1e of its group's scale (%s), "
            "history %.1e (%s); tol 1e-12%s" % (
                len(d["id"]), dd, group, hd, col,
                "; %d particles migrated" % mig if ranks > 1 else ""))
c.done()
