"""Two ranks give the one-rank answer: positions, velocities and stresses of every particle
agree to 1e-10 relative (to the largest value of each field) after runs in which particles
migrate between ranks, on a uniform grid and on a three-level grid (also with corner tracking,
whose corners migrate with their particles, and with the CPDI domains cpdi and cpdi2, whose
corners' stencils reach across rank borders)."""
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
cases = [("drift", "x", ["-da_processors_x", "2", "-da_processors_y", "1"]),
         ("drift", "y", ["-da_processors_x", "1", "-da_processors_y", "2"]),
         ("drift3", "x", ["-da_processors_x", "2", "-da_processors_y", "1"]),
         ("drift3", "y", ["-da_processors_x", "1", "-da_processors_y", "2"]),
         ("drift3", "x-corners", ["-da_processors_x", "2", "-da_processors_y", "1"]),
         ("drift3", "y-cpdi", ["-da_processors_x", "1", "-da_processors_y", "2"]),
         ("drift3", "x-cpdi2", ["-da_processors_x", "2", "-da_processors_y", "1"])]
serial = {}
for scene, tag, layout in cases:
    opts = "options/%s.opts" % scene
    mode = tag.split("-")[1] if "-" in tag else ""
    extra = ["-gimp_tracking", mode] if mode else []
    key = scene + " ".join(extra)
    if key not in serial:
        d1 = os.path.join(args.work, "%s_np1%s.csv" % (scene, "_" + mode if mode else ""))
        gimptest.run(args, opts, ["-gimp_particle_dump", d1] + extra,
                     outdir=os.path.join(args.work, scene + "_np1" + mode))
        serial[key] = gimptest.read_csv(d1)
    d2 = os.path.join(args.work, "%s_np2_%s.csv" % (scene, tag))
    o2 = gimptest.run(args, opts, ["-gimp_particle_dump", d2] + layout + extra, ranks=2,
                      outdir=os.path.join(args.work, "%s_np2_%s" % (scene, tag)))
    a, b = serial[key], gimptest.read_csv(d2)
    name = "%s %s-split" % (scene, tag)
    c.check(name + " ids", a["id"] == b["id"],
            "%d particles at 1 rank, %d at 2" % (len(a["id"]), len(b["id"])))
    worst, where = 0.0, ""
    for col in ("x", "y", "vx", "vy", "sxx", "syy", "sxy", "szz", "lx", "ly"):
        scale = max(abs(v) for v in a[col])
        err = max(abs(u - v) for u, v in zip(a[col], b[col])) / scale
        if err >= worst:
            worst, where = err, col
    c.check(name + " fields", worst < 1e-10,
            "largest max diff / max |value| = %.2e (%s)" % (worst, where))
    mig = gimptest.summary(o2)["measures"].get("particles_migrated", 0)
    c.check(name + " migration", mig > 0, "%d particle migrations during the 2-rank run" % mig)
c.done()
