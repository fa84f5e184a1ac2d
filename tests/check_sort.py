"""Particles ordered by cell (-gimp_sort_interval; docs/options.md, docs/performance.md).

Every -gimp_sort_interval steps each rank orders its particles by level-0 cell, then id. The
two colliding disks are seeded in cell order; as they move into each other the order breaks
(checked, so that the next check means something), and a sort restores it. Sorting only changes the order of the sums: the particles
after 400 steps (through the impact) equal the unsorted run's to round-off, on 1 and 2 ranks."""
import csv
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
W = args.work
OPTS = "options/disks.opts"


def keys_at_sort(outdir, before, after):
    """The level-0 cell (row by row) of every particle at frame `before`, listed in the order of
    frame `after` (particles matched by X0): a sort at the start of the step between the two
    frames leaves these keys in non-decreasing order."""
    import h5py
    lv = gimptest.summary(outdir)["levels"][0]
    x0, y0, h = lv["box"][0], lv["box"][1], lv["h"]
    nx = int(round((lv["box"][2] - x0) / h)) + 1
    with h5py.File(os.path.join(outdir, "fields.h5"), "r") as f:
        xb = f["particles/%s/x" % before][()]
        Xb = f["particles/%s/X0" % before][()]
        Xa = f["particles/%s/X0" % after][()]
    at = {(X[0], X[1]): x for X, x in zip(Xb, xb)}
    return [int(math.floor((p[1] - y0) / h)) * nx + int(math.floor((p[0] - x0) / h))
            for p in (at[(X[0], X[1])] for X in Xa)]


def ordered(keys):
    return all(a <= b for a, b in zip(keys, keys[1:]))


# The disks move into each other for 300 steps; frames at steps 300 and 301; a sort (if any) at
# the start of step 300.
frames = ["-ts_max_steps", "301", "-gimp_output_interval", "300"]
runs = {}
for interval in (0, 300):
    out = gimptest.run(args, OPTS, frames + ["-gimp_sort_interval", str(interval)],
                       outdir=os.path.join(W, "order%d" % interval))
    runs[interval] = keys_at_sort(out, "step_00000300", "step_00000301")
c.check("unsorted particles leave cell order", not ordered(runs[0]),
        "%d particles; without sorting, the order after 300 steps is %s" %
        (len(runs[0]), "still cell order" if ordered(runs[0]) else "not cell order (as it must be "
                                                                   "for the next check to mean "
                                                                   "something)"))
c.check("ordered by cell after a sort", ordered(runs[300]),
        "%d particles in non-decreasing level-0 cell order after the sort at step 300" %
        len(runs[300]))


def dump_run(name, extra, ranks=1):
    dump = os.path.join(W, name + ".csv")
    gimptest.run(args, OPTS, ["-ts_max_steps", "400", "-gimp_particle_dump", dump] + extra,
                 ranks=ranks, outdir=os.path.join(W, name))
    with open(dump) as f:
        return list(csv.DictReader(f))


def worst(a, b):
    """The largest difference of each quantity relative to its largest value (dumps by id)."""
    out = 0.0
    for k in ("x", "y", "vx", "vy", "sxx", "syy", "sxy", "V", "lx", "ly"):
        scale = max(abs(float(p[k])) for p in a) or 1.0
        out = max(out, max(abs(float(p[k]) - float(q[k])) for p, q in zip(a, b)) / scale)
    return out


unsorted = dump_run("unsorted", ["-gimp_sort_interval", "0"])
for ranks in (1, 2):
    s = dump_run("sorted%d" % ranks, ["-gimp_sort_interval", "25"], ranks)
    same_ids = [p["id"] for p in s] == [p["id"] for p in unsorted]
    d = worst(unsorted, s) if same_ids else float("inf")
    c.check("sorted = unsorted, %d rank(s)" % ranks, d <= 1e-12,
            "%d particles after 400 steps, sorted every 25 steps: largest difference relative "
            "to the largest value %.1e" % (len(s), d))
c.done()
