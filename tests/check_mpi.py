"""Two ranks give the one-rank answer: positions, velocities and stresses of every particle
agree to 1e-10 relative after a run in which particles migrate between ranks."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
for layout in (["-da_processors_x", "2", "-da_processors_y", "1"],
               ["-da_processors_x", "1", "-da_processors_y", "2"]):
    tag = "x" if layout[1] == "2" else "y"
    d1 = os.path.join(args.work, "np1.csv")
    d2 = os.path.join(args.work, "np2_%s.csv" % tag)
    gimptest.run(args, "runs/drift.opts", ["-gimp_particle_dump", d1],
                 outdir=os.path.join(args.work, "np1"))
    o2 = gimptest.run(args, "runs/drift.opts", ["-gimp_particle_dump", d2] + layout, ranks=2,
                      outdir=os.path.join(args.work, "np2_" + tag))
    a, b = gimptest.read_csv(d1), gimptest.read_csv(d2)
    c.check("ids " + tag, a["id"] == b["id"], "%d particles at 1 rank, %d at 2" %
            (len(a["id"]), len(b["id"])))
    worst = 0.0
    for col in ("x", "y", "vx", "vy", "sxx", "syy", "sxy", "szz"):
        scale = max(abs(v) for v in a[col])
        err = max(abs(u - v) for u, v in zip(a[col], b[col])) / scale
        worst = max(worst, err)
        c.check("%s %s" % (col, tag), err < 1e-10, "max diff / max |value| = %.2e" % err)
    s = gimptest.summary(o2)
    mig = s["measures"].get("particles_migrated", 0)
    c.check("migration " + tag, mig > 0, "%d particle migrations during the 2-rank run" % mig)
c.done()
