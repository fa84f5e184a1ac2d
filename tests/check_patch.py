"""Patch test: a free block under constant tractions, damped to rest, is uniformly stressed:
sxx = p within 0.5 % at every particle, syy and sxy below 0.5 % of p, plane strain szz = nu p."""
import os
import gimptest

args = gimptest.parse_args()
dump = os.path.join(args.work, "patch_particles.csv")
out = gimptest.run(args, "runs/patch.opts", ["-gimp_particle_dump", dump])
p, nu, E = 1e4, 0.3, 1e7
d = gimptest.read_csv(dump)
c = gimptest.Checks()
n = len(d["sxx"])
err_xx = max(abs(s / p - 1) for s in d["sxx"])
err_yy = max(abs(s) / p for s in d["syy"])
err_xy = max(abs(s) / p for s in d["sxy"])
err_zz = max(abs(s / (nu * p) - 1) for s in d["szz"])
c.check("sxx", err_xx < 0.005, "max |sxx/p - 1| = %.2e over %d particles" % (err_xx, n))
c.check("syy", err_yy < 0.005, "max |syy|/p = %.2e" % err_yy)
c.check("sxy", err_xy < 0.005, "max |sxy|/p = %.2e" % err_xy)
c.check("szz", err_zz < 0.005, "max |szz/(nu p) - 1| = %.2e" % err_zz)
# Elongation: plane strain exx = (1 - nu^2) p / E; from the extreme particle columns.
xs = sorted(set(round(x, 9) for x in d["x"]))
s = gimptest.summary(out)
ke = s["energy"]["kinetic"]
c.check("at rest", ke < 1e-5 * s["energy"]["strain"],
        "kinetic %.3e J vs strain %.3e J" % (ke, s["energy"]["strain"]))
exx = (1 - nu ** 2) * p / E
span0 = 1.0 - 0.025 * 2  # distance between the first and last particle centres initially
span = max(d["x"]) - min(d["x"])
c.check("strain", abs((span / span0 - 1) / exx - 1) < 0.005,
        "exx measured %.6e, exact %.6e" % (span / span0 - 1, exx))
c.done()
