"""Two elastic disks colliding (options/disks.opts; docs/validation.md "Colliding disks"): the
disks are cut from the grid exactly (their particles' volumes add up to 2 pi r^2 to 1e-12), the
total energy (kinetic + strain, no damping) stays within 1 % of its initial value through the
impact and the rebound on one level and with a finer level around the contact zone, the disks
rebound (each moves away from the other at the end, the two velocities opposite to 1e-9 by the
scene's symmetry), and 2 ranks give the 1-rank particles to round-off."""
import math
import os
import gimptest

args = gimptest.parse_args()
c = gimptest.Checks()
R = 0.2


def run(name, extra=(), ranks=1):
    out = os.path.join(args.work, name)
    dump = os.path.join(args.work, name + ".csv")
    gimptest.run(args, "options/disks.opts", list(extra) + ["-gimp_particle_dump", dump],
                 ranks=ranks, outdir=out)
    return gimptest.history(out), gimptest.read_csv(dump)


def energy_drift(hist):
    e = [k + s for k, s in zip(hist["kinetic"], hist["strain"])]
    return max(abs(x / e[0] - 1) for x in e)


def disk_velocities(rows):
    """Volume-weighted mean velocity of each disk (disk 0 is the one below the diagonal
    x + y = 1 at the end: the disks rebound along it)."""
    out = []
    for below in (True, False):
        sel = [i for i, (x, y) in enumerate(zip(rows["x"], rows["y"])) if (x + y < 1) == below]
        v = sum(rows["V"][i] for i in sel)
        out.append((sum(rows["V"][i] * rows["vx"][i] for i in sel) / v,
                    sum(rows["V"][i] * rows["vy"][i] for i in sel) / v, len(sel)))
    return out


gimptest.run(args, "options/disks.opts",
                  ["-ts_max_steps", "0", "-gimp_particle_dump", os.path.join(args.work, "seed.csv")],
                  outdir=os.path.join(args.work, "seed"))
seed = gimptest.read_csv(os.path.join(args.work, "seed.csv"))
area = sum(seed["V"])  # thickness 1 m
c.check("disks cut exactly", abs(area / (2 * math.pi * R * R) - 1) < 1e-12,
        "particle volumes / 2 pi r^2 - 1 = %.1e (tol 1e-12), %d particles"
        % (area / (2 * math.pi * R * R) - 1, len(seed["V"])))

for name, extra in (("one level", []),
                    ("two levels", ["-gimp_levels", "2", "-gimp_level1_box", "0.3,0.3,0.7,0.7"])):
    hist, rows = run(name.replace(" ", "_"), extra)
    d = energy_drift(hist)
    c.check("%s: energy" % name, d <= 0.01, "max |E / E0 - 1| = %.4f (tol 0.01)" % d)
    (u0, v0, n0), (u1, v1, n1) = disk_velocities(rows)
    c.check("%s: rebound" % name, u0 < 0 and v0 < 0 and u1 > 0 and v1 > 0 and n0 == n1,
            "disk velocities at t = 3.5 s: (%.5f, %.5f) and (%.5f, %.5f) m/s (initially "
            "+-(0.1, 0.1)); %d and %d particles" % (u0, v0, u1, v1, n0, n1))
    sym = max(abs(u0 + u1), abs(v0 + v1)) / 0.1
    c.check("%s: symmetric" % name, sym < 1e-9, "|v0 + v1| / 0.1 = %.1e (tol 1e-9)" % sym)

_, one = run("np1", ["-ts_max_steps", "350"])
_, two = run("np2", ["-ts_max_steps", "350"], ranks=2)
worst = max(abs(a - b) for k in ("x", "y", "vx", "vy") for a, b in zip(one[k], two[k]))
c.check("2 ranks equal 1 rank", len(one["x"]) == len(two["x"]) and worst < 1e-12,
        "largest difference of x, y, vx, vy after 350 steps (t = 1.5 s, into the impact): %.1e" % worst)
c.done()
